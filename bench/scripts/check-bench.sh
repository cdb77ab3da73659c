#!/usr/bin/env bash
# Whole-process benchmark of `pmacstream check` (issue 3), for the Native AOT binary and the JIT build (dotnet dll):
#   - check on the 1,000,000-line surfacing program: wall, CPU (user+sys) and peak RSS (/usr/bin/time -v)
#   - the same on a file ten times larger: peak RSS must not grow (goal <= 64 MB for both)
#   - check --db on the 1M file: blocks stored per second (goal >= 300,000), into a new file and appended to an
#     existing store
#   - LinuxCNC's stand-alone interpreter `rs274 -g FILE /dev/null` on the 1M file, and the ratio (goal >= 20x)
# Usage: bench/scripts/check-bench.sh [LINES]   (default 1000000; work files go to $BENCH_DIR or a temp dir)
#   REPS=3 (best of N by wall time, rs274 too: RS274_REPS), AOT_BIN=path (skip publishing), SKIP_JIT=1, SKIP_BIG=1.
set -euo pipefail
cd "$(dirname "$0")/../.."
LINES=${1:-1000000}
BIG=$((LINES * 10))
WORK=${BENCH_DIR:-$(mktemp -d /tmp/pmacstream-check-bench.XXXXXX)}
trap '[ -z "${BENCH_DIR:-}" ] && rm -rf "$WORK"' EXIT

dotnet build -c Release src/PmacStream.Cli -v q -nologo >/dev/null
dotnet build -c Release bench/PmacStream.Benchmarks -v q -nologo >/dev/null
AOT=${AOT_BIN:-$(bench/scripts/publish-aot.sh "$WORK/aot" 2>/dev/null | tail -1)}
JIT=(dotnet src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll)
GEN=(dotnet bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks.dll gen-surfacing)

[ -f "$WORK/surf-1x.nc" ] || "${GEN[@]}" "$WORK/surf-1x.nc" "$LINES" >/dev/null
[ -n "${SKIP_BIG:-}" ] || [ -f "$WORK/surf-10x.nc" ] || "${GEN[@]}" "$WORK/surf-10x.nc" "$BIG" >/dev/null

# Runs a command under /usr/bin/time -v, best of $REPS runs by wall time (the build machines are shared and noisy);
# prints "wall_seconds peak_kb cpu_seconds load1" of the fastest run (load1: 1-minute load average just before it).
# The command's stdout goes to $WORK/out.
REPS=${REPS:-3}
measure() {
  local best="" line wall rss cpu load
  for _ in $(seq "$REPS"); do
    load=$(cut -d' ' -f1 /proc/loadavg)
    /usr/bin/time -v "$@" >"$WORK/out" 2>"$WORK/time" || true
    wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$WORK/time" | awk -F: '{ if (NF==3) print $1*3600+$2*60+$3; else print $1*60+$2 }')
    rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$WORK/time")
    cpu=$(awk -F': ' '/User time|System time/ {s+=$2} END {print s}' "$WORK/time")
    line="$wall $rss $cpu $load"
    if [ -z "$best" ] || [ "$(echo "$wall < ${best%% *}" | bc -l)" = 1 ]; then best=$line; cp "$WORK/out" "$WORK/best.out"; fi
  done
  echo "$best"
}

row() { # NAME WALL RSS_KB CPU LOAD NOTE
  printf "| %-34s | %7.2f | %6.2f | %5d | %5s | %s\n" "$1" "$2" "$4" $(($3 / 1024)) "$5" "$6"
}

echo "== pmacstream check benchmark: $LINES lines ($(( $(stat -c %s "$WORK/surf-1x.nc") / 1000000 )) MB), best of $REPS, $(nproc) cores, $(date -u +%H:%MZ)"
echo "| run                                | wall s  | CPU s  | RSS MB| load1 | result"
echo "|------------------------------------|---------|--------|-------|-------|-------"

declare -A T C
bench_one() { # LABEL CMD...
  local label=$1; shift
  read -r t m c l < <(measure "$@" check samples/demo.nc)
  row "$label start-up (demo.nc, 3k lines)" "$t" "$m" "$c" "$l" "$(tail -1 "$WORK/best.out")"
  T[$label.0]=$t; C[$label.0]=$c
  read -r t m c l < <(measure "$@" check "$WORK/surf-1x.nc")
  row "$label check 1x" "$t" "$m" "$c" "$l" "$(tail -1 "$WORK/best.out")"
  T[$label.1]=$t; C[$label.1]=$c
  if [ -z "${SKIP_BIG:-}" ]; then
    read -r t m c l < <(REPS=1 measure "$@" check "$WORK/surf-10x.nc")
    row "$label check 10x (1 run)" "$t" "$m" "$c" "$l" "$(tail -1 "$WORK/best.out")"
  fi
  # A fresh database each run (the rm is part of the measured shell, but takes microseconds).
  read -r t m c l < <(measure bash -c 'rm -f "$1"*; shift; exec "$@"' _ "$WORK/store.db" "$@" check --db "$WORK/store.db" "$WORK/surf-1x.nc")
  local blocks; blocks=$(tail -1 "$WORK/best.out" | awk '{print $(NF-1)}')
  row "$label check --db 1x (new file)" "$t" "$m" "$c" "$l" "$(printf "%.0f blocks/s wall, %.0f blocks per CPU-s (goal >= 300,000/s)" "$(echo "$blocks / $t" | bc -l)" "$(echo "$blocks / $c" | bc -l)")"
  # Appending to an existing store (WAL mode, readers may be open): the database already holds demo.nc.
  rm -f "$WORK/base.db"*
  "$@" check --db "$WORK/base.db" samples/demo.nc >/dev/null
  read -r t m c l < <(measure bash -c 'rm -f "$2"*; cp "$1" "$2"; shift 2; exec "$@"' _ "$WORK/base.db" "$WORK/store2.db" "$@" check --db "$WORK/store2.db" "$WORK/surf-1x.nc")
  blocks=$(tail -1 "$WORK/best.out" | awk '{print $(NF-1)}')
  row "$label check --db 1x (existing)" "$t" "$m" "$c" "$l" "$(printf "%.0f blocks/s wall, %.0f blocks per CPU-s" "$(echo "$blocks / $t" | bc -l)" "$(echo "$blocks / $c" | bc -l)")"
}

bench_one aot "$AOT"
[ -n "${SKIP_JIT:-}" ] || bench_one jit "${JIT[@]}"

RS274=$(command -v rs274 || true)
if [ -z "$RS274" ]; then
  if command -v apt-get >/dev/null && [ "$(id -u)" = 0 ]; then
    echo "rs274 not found: trying apt-get install linuxcnc-uspace ..." >&2
    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends linuxcnc-uspace) >/dev/null 2>&1 || true
  fi
  RS274=$(command -v rs274 || true)
  [ -z "$RS274" ] && [ -x /usr/bin/rs274 ] && RS274=/usr/bin/rs274
fi
if [ -z "$RS274" ]; then
  echo "rs274: NOT AVAILABLE (Debian package linuxcnc-uspace is not installable here); no comparison, our numbers stand alone."
  exit 0
fi

# rs274 interprets the program and writes canonical machining calls; -g runs it without the interactive prompt.
read -r tr mr cr lr < <(REPS=${RS274_REPS:-$REPS} measure "$RS274" -g "$WORK/surf-1x.nc" /dev/null)
row "rs274 -g 1x" "$tr" "$mr" "$cr" "$lr" "LinuxCNC stand-alone interpreter"
echo
for label in aot jit; do
  [ -n "${T[$label.1]:-}" ] || continue
  printf "ratio rs274 / %s check 1x: %5.1fx wall, %5.1fx CPU (goal >= 20x); without our start-up: %5.1fx CPU\n" "$label" \
    "$(echo "$tr / ${T[$label.1]}" | bc -l)" "$(echo "$cr / ${C[$label.1]}" | bc -l)" "$(echo "$cr / (${C[$label.1]} - ${C[$label.0]})" | bc -l)"
done
