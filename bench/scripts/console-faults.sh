#!/usr/bin/env bash
# The console's fault proof over the full matrix (issue 25): every fault kind (limit+, limit-, fatal-following-error,
# amp-fault) injected at a random time into a 20,000-block job under every strategy (chunk, pr, adaptive), against a
# `pmacstream sim` process over TCP: the job must stop on the alarm (exit 1), the alarm must show in status --json,
# and after `alarms clear` (and a jog off a limit) `resume` must end the job with every block executed once, in order
# (the simulator's executed-move log). The test suite runs one job per kind (ConsoleFaultProofTests); this runs all 12.
# Usage: bench/scripts/console-faults.sh [DLL] [SPEED]   (SPEED of the simulator's clock, default 20x; RUNS=N repeats;
#   STRATEGIES="pr" and FAULTS="limit-:2" pick a part of the matrix). About 25 s a run on 2 cores: 12 runs, 5 minutes.
# Prints one PASS/FAIL line per run, with the fault time and seed; exit 0 when all passed.
set -uo pipefail
cd "$(dirname "$0")/../.."
DLL=${1:-src/PmacStream.Cli/bin/Debug/net10.0/pmacstream.dll}
SPEED=${2:-20x}
RUNS=${RUNS:-1}
STRATEGIES=${STRATEGIES:-chunk pr adaptive}
FAULTS=${FAULTS:-limit+:1 limit-:2 fatal-following-error:3 amp-fault:1}
WORK=$(mktemp -d /tmp/pmacstream-console-faults.XXXXXX)
[ -n "${KEEP:-}" ] || trap 'rm -rf "$WORK"' EXIT
python3 - "$WORK/raster.nc" <<'PY'
import sys
lines = ['G21 G17 G90', 'G00 X0 Y0', 'F1500']
for i in range(20000):
    row, col = divmod(i, 200)
    lines.append('G01 X%.2f Y%.2f' % ((col if row % 2 == 0 else 199 - col) * 0.25, row * 0.25))
open(sys.argv[1], 'w').write('\n'.join(lines + ['M30']) + '\n')
PY
fails=0
for run in $(seq 1 "$RUNS"); do
for strategy in $STRATEGIES; do
  for fault in $FAULTS; do
    kind=${fault%%:*}; motor=${fault##*:}
    at=$(python3 -c "import random; print(round(random.uniform(2, 150), 2))")
    dir="$WORK/$strategy-$kind-$run"; mkdir -p "$dir"
    export PMACSTREAM_TABLES="$dir/tables.json" PMACSTREAM_SETTINGS="$dir/settings.json"
    dotnet "$DLL" sim --tcp 0 --speed "$SPEED" --executed-log "$dir/exec.csv" --inject "$kind:$motor@$at" >"$dir/sim.out" 2>&1 &
    sim=$!
    for _ in $(seq 1 100); do grep -q "listening" "$dir/sim.out" 2>/dev/null && break; sleep 0.1; done
    port=$(grep -o '(port [0-9]*)' "$dir/sim.out" | grep -o '[0-9]*')
    T=(--tcp "127.0.0.1:$port" --job-db "$dir/jobs.db")
    verdict=PASS why=
    dotnet "$DLL" home "${T[@]}" >/dev/null 2>&1 || { verdict=FAIL; why="home"; }
    dotnet "$DLL" stream "$dir/../raster.nc" --strategy "$strategy" "${T[@]}" >"$dir/stream.out" 2>&1
    [ $? = 1 ] || { verdict=FAIL; why="stream did not stop on the alarm"; }
    dotnet "$DLL" status --json "${T[@]}" | grep -q "\"code\":\"$kind\"" || { verdict=FAIL; why="$why; alarm not in status"; }
    dotnet "$DLL" alarms clear "${T[@]}" >/dev/null 2>&1
    case $kind in
      limit+) dotnet "$DLL" jog "$(echo XYZ | cut -c"$motor")" -1 "${T[@]}" >/dev/null 2>&1 ;;
      limit-) dotnet "$DLL" jog "$(echo XYZ | cut -c"$motor")" +1 "${T[@]}" >/dev/null 2>&1 ;;
    esac
    job=$(grep -o '^job [0-9]*' "$dir/stream.out" | head -1 | grep -o '[0-9]*')
    dotnet "$DLL" resume --job "$job" --yes "${T[@]}" >"$dir/resume.out" 2>&1 || { verdict=FAIL; why="$why; resume exit $?"; }
    kill -TERM "$sim"; wait "$sim" 2>/dev/null
    python3 - "$dir/exec.csv" "$dir/../raster.nc" <<'PY' || { verdict=FAIL; why="$why; executed log differs"; }
import sys
rows = [l.split(',') for l in open(sys.argv[1]).read().split('\n')[1:] if l]
got = [int(r[1]) for r in rows if r[-1] == '1' and int(r[1]) > 0]
want = [i + 1 for i, l in enumerate(open(sys.argv[2]).read().split('\n')) if l.startswith('G0')]
sys.exit(0 if got == want else 1)
PY
    echo "$verdict $strategy $kind motor $motor at ${at}s: $(grep -o 'alarm at line [0-9]*' "$dir/stream.out" | head -1)${why:+ ($why)}"
    [ "$verdict" = PASS ] || fails=$((fails + 1))
  done
done
done
echo "console-faults: $fails failed"
[ "$fails" = 0 ]
