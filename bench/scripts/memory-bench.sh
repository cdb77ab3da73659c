#!/usr/bin/env bash
# Peak memory where issue 20 found it unbounded, for this tree's CLI or another build (PMACSTREAM_CLI=path/to/
# pmacstream.dll, e.g. main's, for the numbers before):
#  1. stream --sim, each strategy (STRATEGIES, default "chunk adaptive pr"): the in-process simulator's executed-move
#     log (was kept in memory, now checked as it runs). Goal: peak <= 100 MB in every mode;
#  2. pmacstream sim --executed-log + stream --tcp: the simulator server's log (was kept until stop, now streamed);
#  3. pmacstream sim + a client that sends SENDLINE packets and never fetches the replies (were all kept, now at most
#     16 KiB per connection, the oldest dropped);
#  4. check, split and preview of hostile programs (issue 20 phase 2): 1, 2 and 9 MB of 1 MiB lines of "X " (every X a
#     finding: all were held, 420 MB for 1 MB in check), one 9 MB line and ALL_ERRORS_MB (default 256) of all-error
#     lines. Goal: peak <= 64 MB whatever the size. AOT_BIN=path (bench/scripts/publish-aot.sh) is measured too.
#     samples/demo.nc (a clean 3,000-line program) comes first: the floor the hostile files are read against.
# The CLI's runtimeconfig caps the collector's gen0 budget (System.GC.Gen0MaxBudget, src/PmacStream.Cli's project);
# DOTNET_GCgen0MaxBudget or DOTNET_GCgen0size in the environment measure other budgets.
# Usage: bench/scripts/memory-bench.sh [LINES] [PACKETS]   (defaults 220000 and 20000); ONLY=hostile runs section 4 only
set -euo pipefail
cd "$(dirname "$0")/../.."
LINES="${1:-220000}"
PACKETS="${2:-20000}"
ALL_ERRORS_MB="${ALL_ERRORS_MB:-256}"
if [ -z "${PMACSTREAM_CLI:-}" ]; then
  dotnet build src/PmacStream.Cli -c Release -v q -nologo >/dev/null
  PMACSTREAM_CLI="$PWD/src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll"
fi
CLI=(dotnet "$PMACSTREAM_CLI")
WORK=$(mktemp -d /tmp/pmacstream-memory.XXXXXX)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$WORK"' EXIT
peak_kb() { grep VmHWM "/proc/$1/status" | awk '{print $2}'; }

# Section 4's inputs: 1, 2 and 9 MB of 1 MiB lines of "X " (half a million malformed numbers a line), one 9 MB line
# (cut at 1 MiB) and ALL_ERRORS_MB of lines with 250 findings each.
make_hostile() {
  python3 - "$WORK" "$ALL_ERRORS_MB" <<'PY'
import sys
work, mb = sys.argv[1], int(sys.argv[2])
line = "X " * (1 << 19) + "\n"
for n in (1, 2, 9):
    with open(f"{work}/lines-{n}mb.nc", "w") as f:
        f.write(line * n)
with open(f"{work}/one-line-9mb.nc", "w") as f:
    f.write("X " * (9 << 19) + "\n")
junk = "X " * 125 + "\n"
with open(f"{work}/all-errors.nc", "w") as f:
    for _ in range((mb << 20) // len(junk)):
        f.write(junk)
PY
}

hostile() {
  echo "== 4. check, split and preview of hostile programs: peak RSS in MB (goal <= 64)"
  make_hostile
  local builds=("jit:${CLI[*]}")
  [ -n "${AOT_BIN:-}" ] && builds+=("aot:$AOT_BIN")
  printf "%-5s %-24s %9s %9s %9s\n" build file check split preview
  local b name cmd f c row extra
  cp samples/demo.nc "$WORK/demo.nc"
  for b in "${builds[@]}"; do
    name=${b%%:*} cmd=${b#*:}
    for f in demo lines-1mb lines-2mb lines-9mb one-line-9mb all-errors; do
      row=""
      for c in check split preview; do
        extra=(); [ "$c" = preview ] && extra=(--png "$WORK/$f.png")
        rm -rf "$WORK/${f}_chunks"
        # shellcheck disable=SC2086
        /usr/bin/time -f "%M" -o "$WORK/peak" $cmd "$c" "$WORK/$f.nc" "${extra[@]}" >/dev/null 2>"$WORK/err" || true
        row="$row $(tail -n 1 "$WORK/peak" | awk '{printf "%9.1f", $1 / 1024}')"
      done
      printf "%-5s %-24s%s\n" "$name" "$f ($(du -h "$WORK/$f.nc" | cut -f1))" "$row"
    done
  done
}

if [ "${ONLY:-}" = hostile ]; then
  echo "cli: $PMACSTREAM_CLI${AOT_BIN:+; aot: $AOT_BIN}"
  hostile
  exit 0
fi

dotnet build bench/PmacStream.Benchmarks -c Release -v q -nologo >/dev/null
bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks gen-surfacing "$WORK/part.nc" "$LINES" >/dev/null
"${CLI[@]}" split "$WORK/part.nc" >/dev/null
echo "cli: $PMACSTREAM_CLI; program: $LINES lines (surfacing, $(du -h "$WORK/part.nc" | cut -f1))"
rss_kb() { grep VmRSS "/proc/$1/status" | awk '{print $2}'; }

start_sim() { # LOG ARGS... -> sets SIM and PORT
  "${CLI[@]}" sim --tcp 127.0.0.1:0 --homed "${@:2}" >"$1" 2>&1 &
  SIM=$!
  for _ in $(seq 200); do grep -q "listening" "$1" 2>/dev/null && break; sleep 0.05; done
  PORT=$(grep -o "port [0-9]*" "$1" | grep -o "[0-9]*")
}

echo "== 1. stream --sim (built-in simulator, instant clock), goal <= 100 MB"
for strategy in ${STRATEGIES:-chunk adaptive pr}; do
  rm -f "$WORK"/jobs1.db*
  /usr/bin/time -v "${CLI[@]}" stream "$WORK/part.nc" --sim --sim-speed instant --strategy "$strategy" --job-db "$WORK/jobs1.db" >"$WORK/s1.out" 2>"$WORK/s1.err" || true
  echo "$strategy: $(grep -h "^executed" "$WORK/s1.out" || tail -n 3 "$WORK/s1.err"); peak RSS $(grep 'Maximum resident' "$WORK/s1.err" | awk '{print $6}') KB"
done

echo "== 2. pmacstream sim --executed-log, stream --tcp (simulator process measured)"
start_sim "$WORK/sim2.log" --speed instant --executed-log "$WORK/executed.csv"
"${CLI[@]}" stream "$WORK/part.nc" --tcp "127.0.0.1:$PORT" --job-db "$WORK/jobs2.db" >"$WORK/s2.out" 2>&1 || true
grep -h "^executed" "$WORK/s2.out" || tail -n 3 "$WORK/s2.out"
echo "simulator peak RSS $(peak_kb $SIM) KB before stop"
kill -TERM $SIM; wait $SIM || true
echo "executed log: $(($(wc -l <"$WORK/executed.csv") - 1)) moves"

echo "== 3. pmacstream sim, $PACKETS SENDLINE packets (P0..4095) whose replies are never fetched"
start_sim "$WORK/sim3.log" --speed instant
before=$(rss_kb $SIM)
python3 - "$PORT" "$PACKETS" "$SIM" <<'EOF'
import socket, struct, sys
port, n, pid = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
s = socket.create_connection(("127.0.0.1", port))
s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
cmd = b"P0..4095"
packet = struct.pack(">BBHHH", 0x40, 0xB0, 0, 0, len(cmd)) + cmd
for _ in range(n):
    s.sendall(packet)
    s.recv(1)  # SENDLINE answers one byte; the reply text waits for GETLINE, which never comes
status = dict(l.split(":", 1) for l in open("/proc/%s/status" % pid) if ":" in l)
print("sent %d packets; simulator RSS %s with the connection still open" % (n, status["VmRSS"].strip()))
EOF
echo "simulator RSS $before KB before the client; peak $(peak_kb $SIM) KB"
kill -TERM $SIM; wait $SIM || true

hostile
