#!/usr/bin/env bash
# Start from a line of a stored revision (issue 26), on SQLite and (when BENCH_PG names a server) PostgreSQL:
#   - the import (`programs import`: check, decode and store every block in one pass): wall, blocks/s, peak RSS, and
#     the store's size on disk for the program
#   - "start from line L to the preamble shown" (`programs start ID --from-line L`, L = 99% of the program, so 9,900,000
#     of 10M blocks): from the store's stored states, against today's re-interpretation of the source from the top
#     (`--reinterpret`): wall and peak RSS of the whole process, and the planner's own time (stderr)
# Usage: bench/scripts/start-from-line.sh [BLOCKS ...]   (default 1000000; give "1000000 10000000" for both sizes)
#   BENCH_PG=postgres://USER@HOST:PORT/DB (with PGPASSWORD) adds PostgreSQL; psql then measures its size.
#   BENCH_DIR=DIR keeps the work files; SKIP_BUILD=1 takes the Release build as it is; JIT build (Release dll), not AOT.
set -euo pipefail
cd "$(dirname "$0")/../.."
SIZES=("${@:-1000000}")
WORK=${BENCH_DIR:-$(mktemp -d /tmp/pmacstream-start-bench.XXXXXX)}
trap '[ -z "${BENCH_DIR:-}" ] && rm -rf "$WORK"' EXIT

if [ -z "${SKIP_BUILD:-}" ]; then
  dotnet build -c Release src/PmacStream.Cli -v q -nologo >/dev/null
  dotnet build -c Release bench/PmacStream.Benchmarks -v q -nologo >/dev/null
fi
CLI=(dotnet src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll)
GEN=(dotnet bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks.dll gen-surfacing)

# Runs a command under /usr/bin/time -v; prints "wall_seconds peak_kb"; its stdout goes to $WORK/out, stderr to $WORK/err.
measure() {
  /usr/bin/time -v -o "$WORK/time" "$@" >"$WORK/out" 2>"$WORK/err" || { cat "$WORK/err" >&2; return 1; }
  local wall rss
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$WORK/time" | awk -F: '{ if (NF==3) print $1*3600+$2*60+$3; else print $1*60+$2 }')
  rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$WORK/time")
  echo "$wall $rss"
}

pg_bytes() { # total size of the store's tables on the server
  psql "$BENCH_PG" -Atq -c "SELECT COALESCE(SUM(pg_total_relation_size(c.oid)), 0) FROM pg_class c JOIN pg_namespace n ON n.oid = c.relnamespace WHERE n.nspname = 'public' AND c.relkind = 'r'"
}

echo "== start from a line of a stored revision: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%H:%MZ)"
echo "| blocks     | engine   | step                          | wall s  | RSS MB | result"
echo "|------------|----------|-------------------------------|---------|--------|-------"
row() { printf "| %10s | %-8s | %-29s | %7.2f | %6d | %s\n" "$1" "$2" "$3" "$4" $(($5 / 1024)) "$6"; }

for blocks in "${SIZES[@]}"; do
  src="$WORK/surf-$blocks.nc"
  [ -f "$src" ] || "${GEN[@]}" "$src" "$blocks" >/dev/null
  lines=$(wc -l <"$src")
  line=$((lines * 99 / 100))
  engines=(sqlite); [ -n "${BENCH_PG:-}" ] && engines+=(postgres)
  for engine in "${engines[@]}"; do
    if [ "$engine" = sqlite ]; then
      db="$WORK/store-$blocks.db"; rm -f "$db"*; store="sqlite:$db"
    else
      store=$BENCH_PG; before=$(pg_bytes)
    fi
    read -r t m < <(measure "${CLI[@]}" programs import "$src" --store "$store")
    id=$(tail -1 "$WORK/out")
    if [ "$engine" = sqlite ]; then size=$(du -cb "$db"* | tail -1 | cut -f1); else size=$(( $(pg_bytes) - before )); fi
    row "$blocks" "$engine" "import (check+decode+store)" "$t" "$m" "$(printf "%.0f blocks/s; %.0f MB on disk (%.0f bytes/block); source %.0f MB" \
      "$(echo "$blocks / $t" | bc -l)" "$(echo "$size / 1000000" | bc -l)" "$(echo "$size / $blocks" | bc -l)" "$(echo "$(stat -c %s "$src") / 1000000" | bc -l)")"
    for how in store reinterpret; do
      flag=(); [ "$how" = reinterpret ] && flag=(--reinterpret)
      read -r t m < <(measure "${CLI[@]}" programs start "$id" --from-line "$line" "${flag[@]}" --store "$store")
      cp "$WORK/out" "$WORK/preamble-$engine-$blocks-$how"
      row "$blocks" "$engine" "start at line $line ($how)" "$t" "$m" "$(tail -1 "$WORK/err"); $(head -1 "$WORK/out")"
    done
    if cmp -s "$WORK/preamble-$engine-$blocks-store" "$WORK/preamble-$engine-$blocks-reinterpret"; then
      echo "|            | $engine | preambles: identical ($(wc -l <"$WORK/preamble-$engine-$blocks-store") lines)"
    else
      echo "|            | $engine | preambles DIFFER:"; diff "$WORK/preamble-$engine-$blocks-store" "$WORK/preamble-$engine-$blocks-reinterpret" | head -20
    fi
    if [ "$engine" = postgres ]; then "${CLI[@]}" programs rm "$id" --store "$store" >/dev/null; fi
  done
done
