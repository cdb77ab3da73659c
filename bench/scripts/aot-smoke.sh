#!/usr/bin/env bash
# Runs every CLI command from the Native AOT binary and from the JIT build (dotnet pmacstream.dll) and compares:
# same exit codes, and byte-identical output where the output is deterministic (check text/JSON, the --db
# store's rows, split's chunk files and manifest.json, prog1000, plc, preview PNG). stream --sim, demo and resume
# run against the built-in simulator (instant clock) and must finish with exit 0 from both binaries.
# Usage: bench/scripts/aot-smoke.sh AOT_BINARY [JIT_DLL]
#   JIT_DLL defaults to src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll (built first, so it matches the source).
# Exit 0 when every check passed; prints one PASS/FAIL line per check.
set -uo pipefail
cd "$(dirname "$0")/../.."
AOT=${1:?usage: aot-smoke.sh AOT_BINARY [JIT_DLL]}
if [ -n "${2:-}" ]; then JIT_DLL=$2; else
  JIT_DLL=src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll
  dotnet build -c Release src/PmacStream.Cli -v q -nologo >/dev/null
fi
WORK=$(mktemp -d /tmp/pmacstream-aot-smoke.XXXXXX)
[ -n "${KEEP:-}" ] || trap 'rm -rf "$WORK"' EXIT
fails=0

# run NAME EXPECTED_EXIT ARGS...: runs both binaries in $WORK/aot and $WORK/jit (cwd), stdout/stderr captured.
run() {
  local name=$1 want=$2; shift 2
  local a j
  mkdir -p "$WORK/aot" "$WORK/jit"
  (cd "$WORK/aot" && "$AOT" "$@" >"$name.out" 2>"$name.err"); a=$?
  (cd "$WORK/jit" && dotnet "$OLDPWD/$JIT_DLL" "$@" >"$name.out" 2>"$name.err"); j=$?
  if [ "$a" != "$want" ] || [ "$j" != "$want" ]; then
    echo "FAIL $name: exit aot=$a jit=$j, expected $want"; sed 's/^/  aot stderr: /' "$WORK/aot/$name.err" | head -5
    fails=$((fails + 1)); return 1
  fi
  return 0
}

# same NAME FILE...: the named files (relative to each run folder) must be byte-identical.
same() {
  local name=$1; shift
  for f in "$@"; do
    # Messages name the run folder (aot/ or jit/): compare with it replaced.
    case "$f" in *.out|*.err) sed -i -E "s#$WORK/(aot|jit)#WORK#g" "$WORK/aot/$f" "$WORK/jit/$f" ;; esac
    if ! cmp -s "$WORK/aot/$f" "$WORK/jit/$f"; then
      echo "FAIL $name: $f differs between AOT and JIT"; diff <(head -c 2000 "$WORK/aot/$f") <(head -c 2000 "$WORK/jit/$f") | head -10
      fails=$((fails + 1)); return 1
    fi
  done
  echo "PASS $name"
}

R=$PWD
cp samples/demo.nc "$WORK/demo.nc"
printf 'G01 X1 Y2\nG99 X1\nG02 X5 Y5\n' >"$WORK/bad.nc"

run check 0 check "$R/samples/demo.nc" && same check check.out
run check-errors 1 check "$WORK/bad.nc" && same check-errors check-errors.out
run check-zh 1 check --lang zh-CN "$WORK/bad.nc" && same check-zh check-zh.out
run check-json 1 check --json "$WORK/bad.nc" && same check-json check-json.out
run check-json-demo 0 check --json "$R/samples/demo.nc" && same check-json-demo check-json-demo.out
run check-missing 2 check "$WORK/no-such-file.nc" && same check-missing check-missing.err
run check-db 0 check --db store.db "$R/samples/demo.nc" && {
  # The rows, not the file bytes (page layout may legitimately differ): dump every table in a fixed order.
  for d in aot jit; do
    # created times differ run to run; everything else must match.
    python3 - "$WORK/$d/store.db" >"$WORK/$d/store.dump" <<'PY'
import sqlite3, sys
c = sqlite3.connect(sys.argv[1])
for (t,) in c.execute("select name from sqlite_master where type='table' order by name"):
    cols = [r[1] for r in c.execute(f"pragma table_info({t})") if r[1].lower() not in ("created", "createdutc", "created_utc")]
    print(t, cols)
    for row in c.execute(f"select {','.join(cols)} from {t} order by rowid"):
        print(row)
PY
  done
  same check-db check-db.out store.dump
}
run split 0 split "$WORK/demo.nc" --out chunks && same split split.out chunks/manifest.json $(cd "$WORK/aot" && ls chunks/*.pmc)
run prog1000 0 prog1000 && same prog1000 prog1000.out
run plc 0 plc "$R/samples/plc/motor-fwd-rev.ladder" && same plc plc.out
run plc2 0 plc "$R/samples/plc/sand-mould-spindle.ladder" -o plc2.pmc && same plc2 plc2.pmc
run preview 0 preview "$R/samples/demo.nc" --png demo.png --size 400x300 && same preview demo.png
run preview-iso 0 preview "$R/samples/demo.nc" --png iso.png --size 300x200 --view iso && same preview-iso iso.png
run preview-zh 0 preview "$R/samples/demo.nc" --png zh.png --size 600x450 --lang zh-CN && same preview-zh zh.png preview-zh.err
run stream-sim 0 stream "$WORK/demo.nc" --sim --sim-speed instant --job-db jobs.db && echo "PASS stream-sim"
run stream-sim-from-line 0 stream "$WORK/demo.nc" --sim --sim-speed instant --from-line 1500 -y --job-db jobs.db && echo "PASS stream-sim-from-line"
run resume-none 2 resume --sim --job-db missing.db && same resume-none resume-none.err
run demo 0 demo --sim-speed instant && echo "PASS demo"
run help 0 --help && same help help.out

# The AOT binary on both ends of the wire: `sim` serving Ethernet (and serial through a socat pty pair when socat
# is installed) and `stream --tcp/--serial` running demo.nc against it.
wire() { # NAME SIM_ARGS... -- STREAM_ARGS...
  local name=$1; shift
  local sim_args=() ; while [ "$1" != "--" ]; do sim_args+=("$1"); shift; done; shift
  "$AOT" sim --homed --speed instant "${sim_args[@]}" >"$WORK/$name.sim" 2>&1 &
  local sim=$!
  for _ in $(seq 50); do grep -q "listening\|serving" "$WORK/$name.sim" && break; sleep 0.1; done
  local port; port=$(grep -oE 'port [0-9]+' "$WORK/$name.sim" | head -1 | cut -d' ' -f2)
  local args=("${@//PORT/$port}")
  if (cd "$WORK" && timeout 120 "$AOT" stream demo.nc "${args[@]}" --job-db "$name.jobs.db" >"$name.out" 2>&1) &&
     grep -q "executed 3207 of 3207 blocks" "$WORK/$name.out"; then echo "PASS $name"
  else echo "FAIL $name"; tail -3 "$WORK/$name.out"; fails=$((fails + 1)); fi
  kill "$sim" 2>/dev/null; wait "$sim" 2>/dev/null
}
wire stream-tcp --tcp 127.0.0.1:0 -- --tcp 127.0.0.1:PORT
if command -v socat >/dev/null; then
  socat pty,raw,echo=0,link="$WORK/pty-a" pty,raw,echo=0,link="$WORK/pty-b" 2>/dev/null &
  SOCAT=$!
  for _ in $(seq 50); do [ -e "$WORK/pty-b" ] && break; sleep 0.1; done
  wire stream-serial --tcp none --serial "$WORK/pty-a" -- --serial "$WORK/pty-b"
  kill "$SOCAT" 2>/dev/null; wait "$SOCAT" 2>/dev/null
else
  echo "SKIP stream-serial (socat not installed)"
fi

if [ "$fails" = 0 ]; then echo "all AOT smoke checks passed ($AOT)"; else echo "$fails AOT smoke check(s) FAILED"; fi
exit $((fails > 0))
