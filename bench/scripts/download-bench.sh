#!/usr/bin/env bash
# Download benchmark (issue 6): a 1,000,000-line program over TCP loopback to the simulator's VR_PMAC server,
# WRITEBUFFER batching vs one GETRESPONSE per line, behind a minimal endpoint ("fast": transport only) and the
# simulator engine in instant mode ("sim"). Mean is the time per line (line-at-a-time measured on the first 100,000
# lines); prints BenchmarkDotNet's table and lines/s = 1 / Mean.
set -euo pipefail
cd "$(dirname "$0")/../.."
log=/tmp/pmacstream-download-bench.log
dotnet run -c Release --project bench/PmacStream.Benchmarks -- --filter '*DownloadBenchmark*' >"$log" 2>&1
grep -E '^\|' "$log"
grep -E '^\|' "$log" | awk -F'|' '/WriteBufferBatches|LineAtATime/ {
  v=$4; gsub(/[ ,]/, "", v); unit=v; sub(/^[0-9.]+/, "", unit); sub(/[^0-9.].*$/, "", v);
  s = (unit=="ms") ? v/1000 : (unit=="s") ? v : (unit=="us"||unit=="μs") ? v/1e6 : v/1e9;
  printf "%-20s %-6s %10.0f lines/s\n", $2, $3, 1/s }'
