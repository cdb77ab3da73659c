#!/usr/bin/env bash
# Download benchmark (issue 6): a 1,000,000-line program over TCP loopback to the simulator's VR_PMAC server,
# WRITEBUFFER batching vs one GETRESPONSE per line. Prints BenchmarkDotNet's table; lines/s = 1e6 / Mean.
# Usage: bench/scripts/download-bench.sh [ENGINE...]   (fast = transport only; sim = the simulator engine, instant)
set -euo pipefail
cd "$(dirname "$0")/../.."
engines=("${@:-fast}")
dotnet build -c Release bench/PmacStream.Benchmarks >/dev/null
for e in "${engines[@]}"; do
  dotnet run -c Release --no-build --project bench/PmacStream.Benchmarks -- \
    --filter '*DownloadBenchmark*' --params "Engine=$e" --join \
    | tee "/tmp/pmacstream-download-bench-$e.log" | grep -E '^\|' || true
  awk -v e="$e" -F'|' '/WriteBufferBatches|LineAtATime/ {
      gsub(/ /, "", $5); v=$5; unit=v; sub(/[0-9.,]+/, "", unit); gsub(/[^0-9.]/, "", v);
      s = (unit=="ms") ? v/1000 : (unit=="s") ? v : (unit=="us"||unit=="μs") ? v/1e6 : v;
      printf "%s %-20s %.0f lines/s\n", e, $2, 1000000/s }' "/tmp/pmacstream-download-bench-$e.log" || true
done
