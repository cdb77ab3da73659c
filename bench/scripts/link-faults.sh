#!/usr/bin/env bash
# Real link faults between the streamer and the simulator (issue 20): two network namespaces joined by two TUN devices
# and a user-space netem (netem-relay.py: delay, jitter, loss, reordering, because this kernel has no sch_netem), the
# link taken down for DOWN_FOR seconds mid-job. `pmacstream sim` runs in one namespace at real time, `pmacstream
# stream --tcp` in the other (then `resume --yes` while the job is not done, as an operator would); the simulator's
# executed-move log must show every block once, in order. Underruns are the simulator's own count.
#
# Needs root, ip(8), /dev/net/tun and python3. Usage: sudo bench/scripts/link-faults.sh
# Environment (defaults): STRATEGIES="full chunk pr adaptive" RATES="1000 5000" (blocks/s) BLOCKS=20000 PR_BLOCKS=4000
#   DOWN_AT=3 (s after the host first reports an executing line) DOWN_FOR=5 (s) DELAY_MS=2 JITTER_MS=1 LOSS=0.01 REORDER=0.05 SEED=1 PMACSTREAM_CLI=path/to/pmacstream.dll
#   MAX_UNDERRUNS=N fails a run of the full strategy (the default) with more underruns than N (CI: 0).
#   DOWN_FOR=0 is the no-outage mode: the link is never taken down (only delay, jitter, loss and reordering).
#   KEEP=1 keeps the work folder. Prints one result line per run and exits 1 if any run lost, repeated or reordered a
#   block (or starved past MAX_UNDERRUNS), 2 when it cannot run here, 3 when the CLI does not build (PMACSTREAM_CLI given: used as it is, not rebuilt).
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$PWD
STRATEGIES="${STRATEGIES:-full chunk pr adaptive}"
MAX_UNDERRUNS="${MAX_UNDERRUNS:-}"
RATES="${RATES:-1000 5000}"
BLOCKS="${BLOCKS:-20000}"
PR_BLOCKS="${PR_BLOCKS:-4000}"
DOWN_AT="${DOWN_AT:-3}"
DOWN_FOR="${DOWN_FOR:-5}"
DELAY_MS="${DELAY_MS:-2}" JITTER_MS="${JITTER_MS:-1}" LOSS="${LOSS:-0.01}" REORDER="${REORDER:-0.05}" SEED="${SEED:-1}"

[ "$(id -u)" = 0 ] || { echo "link-faults: needs root (network namespaces and TUN devices)"; exit 2; }
[ -c /dev/net/tun ] || { echo "link-faults: no /dev/net/tun"; exit 2; }
# A built CLI given is used as it is; otherwise it is built here, and a build that fails is reported as such (exit 3),
# never as a run that lost a block.
if [ -n "${PMACSTREAM_CLI:-}" ]; then
  [ -f "$PMACSTREAM_CLI" ] || { echo "link-faults: PMACSTREAM_CLI=$PMACSTREAM_CLI: no such file"; exit 2; }
else
  BUILD_LOG=$(mktemp /tmp/pmacstream-linkfaults-build.XXXXXX)
  if ! dotnet build src/PmacStream.Cli -c Release -v q -nologo >"$BUILD_LOG" 2>&1; then
    echo "link-faults: BUILD FAILED (dotnet build src/PmacStream.Cli -c Release); nothing was run. Last lines of the build:"
    tail -n 20 "$BUILD_LOG"
    rm -f "$BUILD_LOG"
    exit 3
  fi
  rm -f "$BUILD_LOG"
  PMACSTREAM_CLI="$ROOT/src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll"
fi
CLI=(dotnet "$PMACSTREAM_CLI")

# Names and addresses of this run only: other engineers may run it on the same machine at the same time.
ID=$$
NS_SIM="pmsim$ID" NS_HOST="pmhost$ID" TUN_SIM="pmS$ID" TUN_HOST="pmH$ID"
NET="10.$(( (ID >> 8) % 200 + 20 )).$(( ID % 250 ))"
SIM_ADDR="$NET.1" HOST_ADDR="$NET.2" PORT=1025
WORK=$(mktemp -d /tmp/pmacstream-linkfaults.XXXXXX)
RELAY_PID="" SIM_PID=""

cleanup() {
  [ -n "$SIM_PID" ] && kill -TERM "$SIM_PID" 2>/dev/null || true
  [ -n "$RELAY_PID" ] && kill -TERM "$RELAY_PID" 2>/dev/null || true
  wait 2>/dev/null || true
  ip netns del "$NS_SIM" 2>/dev/null || true
  ip netns del "$NS_HOST" 2>/dev/null || true
  [ -n "${KEEP:-}" ] && echo "link-faults: work folder kept: $WORK" || rm -rf "$WORK"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

ip netns add "$NS_SIM"
ip netns add "$NS_HOST"
ip -n "$NS_SIM" link set lo up
ip -n "$NS_HOST" link set lo up

# A program of N moves of 0.25 mm at the feed that makes RATE blocks per second, a zig-zag raster.
make_program() { # RATE N OUT
  python3 - "$1" "$2" "$3" <<'EOF'
import sys
rate, n, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
step = 0.25
with open(out, "w") as f:
    f.write("G21 G17 G90\nG00 X0 Y0 Z0\nG01 F%d\n" % (rate * step * 60))
    for i in range(n):
        row, col = divmod(i, 400)
        f.write("G01 X%.2f Y%.2f\n" % ((col if row % 2 == 0 else 399 - col) * step, row * step))
    f.write("M30\n")
EOF
}

# Every block once and in order: the executed log's blocks (a block starts at a row marked block=1, the move its
# synchronous assignment M0==line fired on, or where the line changes; its further moves are not counted; 0 is left
# out) against the synchronous assignments M0==line of the chunks, in order (they rise through the program). So a
# one-move block run twice in a row counts twice. Lost and repeated are counted by line; a break in order is a line
# executed after a later one (or the same line again).
check_log() { # LOG CHUNK_DIR -> "executed expected lost repeated breaks breaks-without-repeats first-break lines-run-twice"
  python3 - "$1" "$2" <<'EOF'
import csv, glob, re, sys
from collections import Counter
log, chunks = sys.argv[1], sys.argv[2]
expected = []
for path in sorted(glob.glob(chunks + "/*.pmc")):
    for line in open(path, encoding="ascii"):
        m = re.match(r"M0==(\d+)", line)
        if m:
            expected.append(int(m.group(1)))
executed, last = [], 0
with open(log) as f:
    for row in csv.DictReader(f):
        n = int(row["line"])
        if n > 0 and (row.get("block") == "1" or n != last):
            executed.append(n)
        last = n if n > 0 else last
want, got = Counter(expected), Counter(executed)
lost = sum(max(0, c - got[k]) for k, c in want.items())
repeated = sum(max(0, c - want[k]) for k, c in got.items())
breaks = [i for i in range(1, len(executed)) if executed[i] <= executed[i - 1]]
first = "line %d after line %d" % (executed[breaks[0]], executed[breaks[0] - 1]) if breaks else "-"
twice = sorted(k for k, c in got.items() if c > want[k])
runs = "%d-%d" % (twice[0], twice[-1]) if twice else "-"
# Order once the repeats' second runs are left out: a break left is a reordering, not only a repeat.
once, kept = [], Counter()
for x in executed:
    kept[x] += 1
    if kept[x] <= want[x]:
        once.append(x)
reordered = sum(1 for i in range(1, len(once)) if once[i] <= once[i - 1])
print(len(executed), len(expected), lost, repeated, len(breaks), reordered, first.replace(" ", "_"), runs)
EOF
}

run_one() { # STRATEGY RATE
  local strategy=$1 rate=$2 blocks=$BLOCKS
  [ "$strategy" = pr ] && blocks=$PR_BLOCKS
  local dir="$WORK/$strategy-$rate"
  mkdir -p "$dir"
  make_program "$rate" "$blocks" "$dir/part.nc"
  "${CLI[@]}" split "$dir/part.nc" >/dev/null

  # The relay creates both TUN devices; each is moved into its namespace and addressed as a point-to-point link.
  python3 "$ROOT/bench/scripts/netem-relay.py" "$TUN_SIM" "$TUN_HOST" --delay-ms "$DELAY_MS" --jitter-ms "$JITTER_MS" \
    --loss "$LOSS" --reorder "$REORDER" --seed "$SEED" --stats "$dir/relay.json" >"$dir/relay.out" 2>"$dir/relay.err" &
  RELAY_PID=$!
  for _ in $(seq 50); do grep -q ready "$dir/relay.out" 2>/dev/null && break; sleep 0.1; done
  ip link set "$TUN_SIM" netns "$NS_SIM"
  ip link set "$TUN_HOST" netns "$NS_HOST"
  ip -n "$NS_SIM" addr add "$SIM_ADDR/30" dev "$TUN_SIM"
  ip -n "$NS_HOST" addr add "$HOST_ADDR/30" dev "$TUN_HOST"
  ip -n "$NS_SIM" link set "$TUN_SIM" up
  ip -n "$NS_HOST" link set "$TUN_HOST" up

  ip netns exec "$NS_SIM" "${CLI[@]}" sim --tcp "$SIM_ADDR:$PORT" --homed --speed realtime --executed-log "$dir/executed.csv" \
    >"$dir/sim.log" 2>&1 &
  SIM_PID=$!
  for _ in $(seq 100); do grep -q "listening" "$dir/sim.log" 2>/dev/null && break; sleep 0.1; done

  local start=$SECONDS
  ip netns exec "$NS_HOST" "${CLI[@]}" stream "$dir/part.nc" --tcp "$SIM_ADDR:$PORT" --strategy "$strategy" \
    --job-db "$dir/jobs.db" >"$dir/host.log" 2>&1 &
  local host=$!
  # DOWN_AT counts from the host's first progress report of an executing line, not from the launch: on a loaded
  # machine the host's start-up alone can take longer than DOWN_AT, and a link taken down before the job starts
  # tests nothing.
  for _ in $(seq 600); do
    grep -q " line [1-9]" "$dir/host.log" 2>/dev/null && break
    kill -0 "$host" 2>/dev/null || break
    sleep 0.1
  done
  if [ "$DOWN_FOR" != 0 ]; then
    sleep "$DOWN_AT"
    ip -n "$NS_HOST" link set "$TUN_HOST" down
    sleep "$DOWN_FOR"
    ip -n "$NS_HOST" link set "$TUN_HOST" up
  fi
  local rc=0 resumes=0
  wait "$host" || rc=$?
  # As an operator would: resume while the job is not done (the simulator still holds it).
  while [ "$rc" != 0 ] && [ "$resumes" -lt 5 ]; do
    resumes=$((resumes + 1))
    rc=0
    ip netns exec "$NS_HOST" "${CLI[@]}" resume --job-db "$dir/jobs.db" --yes >>"$dir/host.log" 2>&1 || rc=$?
  done
  local took=$((SECONDS - start))

  kill -TERM "$SIM_PID"; wait "$SIM_PID" || true; SIM_PID=""
  kill -TERM "$RELAY_PID"; wait "$RELAY_PID" || true; RELAY_PID=""
  local underruns
  underruns=$(grep -o "[0-9]* underruns" "$dir/sim.log" | tail -n 1 | grep -o "[0-9]*" || echo "?")
  # The least lead the host saw (seconds of motion ahead of the executing block while it still had lines to send).
  local lead
  lead=$(grep -o "worst lead [0-9.]* s" "$dir/host.log" | awk '{print $3}' | sort -g | head -n 1)
  [ -n "$lead" ] || lead="?"
  local executed expected lost repeated breaks reordered first twice
  read -r executed expected lost repeated breaks reordered first twice < <(check_log "$dir/executed.csv" "$dir/part_chunks")
  local verdict=ok
  if [ "$lost$repeated$breaks" != 000 ]; then
    verdict="BROKEN (first break: ${first//_/ }; lines run twice: $twice)"
    KEEP=1 # a broken run's logs (executed moves, host and simulator output) are the evidence: never deleted
  elif [ -n "$MAX_UNDERRUNS" ] && [ "$strategy" = full ] && ! [ "$underruns" -le "$MAX_UNDERRUNS" ] 2>/dev/null; then
    verdict="STARVED ($underruns underruns, at most $MAX_UNDERRUNS allowed)"
  fi
  printf '%-8s %5s blocks/s  %6s of %6s blocks  lost %s repeated %s order breaks %s  underruns %-6s worst lead %-6s s  host exit %s after %s resume(s), %3ss  relay %s  %s\n' \
    "$strategy" "$rate" "$executed" "$expected" "$lost" "$repeated" "$breaks" "$underruns" "$lead" "$rc" "$resumes" "$took" \
    "$(tr -d '{}"' <"$dir/relay.json" 2>/dev/null)" "$verdict"
  [ "$verdict" = ok ]
}

outage="link down ${DOWN_FOR}s at ${DOWN_AT}s"
[ "$DOWN_FOR" = 0 ] && outage="no outage"
echo "link-faults: $DELAY_MS ms +- $JITTER_MS ms, loss $LOSS, reorder $REORDER each way, seed $SEED; $outage; sim $SIM_ADDR, host $HOST_ADDR"
failed=0
for rate in $RATES; do
  for strategy in $STRATEGIES; do
    run_one "$strategy" "$rate" || failed=1
  done
done
exit "$failed"
