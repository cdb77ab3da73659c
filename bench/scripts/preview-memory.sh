#!/usr/bin/env bash
# Whole-process memory and time of `pmacstream preview` on a large program (issue 10: a 1 GB program must draw with
# peak memory at most 200 MB). Generates a deterministic surfacing program (about 36 bytes a line), renders it in
# the xy and iso views, prints peak RSS and wall time from /usr/bin/time -v, and deletes the data afterwards.
#
#   bench/scripts/preview-memory.sh [LINES]        default 29000000 lines, about 1.04 GB
set -euo pipefail
LINES="${1:-29000000}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/pmacstream-preview-bench.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT

if [ ! -x /usr/bin/time ]; then
  echo "preview-memory: /usr/bin/time is needed (apt-get install time)" >&2
  exit 2
fi

cd "$ROOT"
dotnet build -c Release src/PmacStream.Cli -nologo -v q >/dev/null
dotnet build -c Release bench/PmacStream.Benchmarks -nologo -v q >/dev/null
dotnet bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks.dll gen-surfacing "$WORK/big.nc" "$LINES"
BYTES=$(stat -c %s "$WORK/big.nc")

for VIEW in xy iso; do
  /usr/bin/time -v -o "$WORK/time-$VIEW.txt" \
    dotnet src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll preview "$WORK/big.nc" --png "$WORK/big-$VIEW.png" --view "$VIEW" \
    | grep -v '%' || true
  RSS_KB=$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$WORK/time-$VIEW.txt")
  WALL=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$WORK/time-$VIEW.txt")
  CPU=$(awk -F': ' '/User time/ {u = $2} /System time/ {s = $2} END {print u + s}' "$WORK/time-$VIEW.txt")
  # CPU time is the steadier figure on a shared machine; wall time includes waiting for a core.
  printf 'preview --view %-3s  program %d lines, %.2f GB  peak RSS %.1f MB  CPU %.1f s  wall %s  (%.1f MB/s of file per wall second)\n' \
    "$VIEW" "$LINES" "$(echo "$BYTES / 1000000000" | bc -l)" "$(echo "$RSS_KB / 1024" | bc -l)" "$CPU" "$WALL" \
    "$(awk -v b="$BYTES" -v w="$WALL" 'BEGIN { n = split(w, p, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + p[i]; print b / 1e6 / s }')"
done
