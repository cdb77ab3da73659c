#!/usr/bin/env bash
# Streaming benchmarks (issue 7): underruns and host CPU per strategy at 1000 blocks/s over a 2 ms link,
# and peak memory streaming a large program. Usage: bench/scripts/stream-bench.sh [LINES] [MEGABYTES]
set -euo pipefail
cd "$(dirname "$0")/../.."
LINES="${1:-1000000}"
MB="${2:-1000}"
dotnet build -c Release bench/PmacStream.Benchmarks -v q -nologo
B=bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks
echo "== CPU and underruns: $LINES blocks at 1000 blocks/s, 2 ms simulated link delay"
"$B" stream-bench cpu "$LINES"
echo "== memory: streaming a ~$MB MB program (split first, then streamed by a fresh process)"
"$B" stream-bench memory "$MB" --split-only
/usr/bin/time -v "$B" stream-bench stream-only "${TMPDIR:-/tmp}/pmacstream-bench/mem/chunks/manifest.json" 2>&1 | grep -E "move times|Chunk|Adaptive|Maximum resident"
rm -rf "${TMPDIR:-/tmp}/pmacstream-bench/mem"
