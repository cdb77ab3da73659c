#!/usr/bin/env bash
# What `stream FILE` costs before streaming a file the store does not hold yet (issue 26: the import in the same pass as
# the check and split). For each size, a `gen-surfacing` program is prepared into a fresh store both ways, alternately:
#   two-pass: `programs import` (read, check, decode, store), then the revision's preparation (read, check, split) - before;
#   one-pass: the job service's preparation with the import (one read: check, decode, store and split together) - now.
# Columns: wall seconds, CPU seconds (user+sys), peak RSS (MB, /usr/bin/time), store size (MB), load before.
# Usage: [RUNS=2] [BENCH_PG=postgres://...] bench/scripts/one-pass-bench.sh [LINES ...]   (default 1000000)
# With BENCH_PG set, each run also goes into that PostgreSQL store (kept there: delete them with `programs rm`; the
# program differs per run anyway: a comment line of its own on top).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
runs="${RUNS:-2}"
sizes=("${@:-1000000}")
work="$(mktemp -d /tmp/pmacstream-one-pass.XXXXXX)"
trap 'rm -rf "$work"' EXIT
dotnet build -c Release "$root/bench/PmacStream.Benchmarks" -v q -nologo >/dev/null
bench=(dotnet "$root/bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks.dll")
echo "one-pass-bench: $(nproc) CPUs, runs $runs"
printf '%-9s %-8s %-9s %6s %8s %8s %8s %6s\n' lines engine mode run wall_s cpu_s rss_MB store_MB
for lines in "${sizes[@]}"; do
  base="$work/base-$lines.nc"
  "${bench[@]}" gen-surfacing "$base" "$lines" >/dev/null
  for run in $(seq 1 "$runs"); do
    for mode in two-pass one-pass; do
      for engine in sqlite ${BENCH_PG:+postgres}; do
        dir="$work/$lines-$run-$mode-$engine"; mkdir -p "$dir"
        src="$dir/part.nc"; { echo "($mode $run $RANDOM$RANDOM)"; cat "$base"; } > "$src"
        if [[ $engine == sqlite ]]; then store="sqlite:$dir/store.db"; else store="$BENCH_PG"; fi
        load=$(cut -d' ' -f1 /proc/loadavg)
        /usr/bin/time -f '%e %U %S %M' -o "$dir/time" "${bench[@]}" prepare-import "$src" "$store" "$mode" "$dir/chunks" > "$dir/out" 2>&1 || { cat "$dir/out"; exit 1; }
        read -r wall user sys rss < "$dir/time"
        size="-"; [[ $engine == sqlite ]] && size=$(du -sm "$dir"/store.db* | awk '{s+=$1} END {print s}')
        printf '%-9s %-8s %-9s %6s %8s %8.2f %8d %6s  load %s\n' "$lines" "$engine" "$mode" "$run" "$wall" "$(echo "$user + $sys" | bc)" "$((rss / 1024))" "$size" "$load"
        grep -q "imported in the split's pass: $([[ $mode == one-pass ]] && echo 1 || echo 0)" "$dir/out" || { echo "unexpected: $(cat "$dir/out")"; exit 1; }
        rm -rf "$dir"
      done
    done
  done
done
