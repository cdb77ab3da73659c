#!/usr/bin/env bash
# Whole-process benchmark of `pmacstream split` (issue 4): MB/s and peak RSS on the 1,000,000-line generated
# surfacing program and on a ~1 GB one. Goals: >= 300 MB/s, <= 64 MB peak RSS.
# Usage: bench/scripts/split-bench.sh [WORKDIR] [BIG_LINES]
# Runs each file twice: `--force` (the splitter alone: one streamed pass) and the default (checker pass first,
# then the splitter). Generated data and chunks are deleted at the end (also on failure).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="${1:-$(mktemp -d /tmp/pmacstream-split-bench.XXXXXX)}"
big_lines="${2:-29800000}"   # ~36 bytes a line: ~1.07 GB
mkdir -p "$work"
trap 'rm -rf "$work"' EXIT

dotnet build -c Release "$root/src/PmacStream.Cli" -v q -nologo >/dev/null
dotnet build -c Release "$root/bench/PmacStream.Benchmarks" -v q -nologo >/dev/null
cli="$root/src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll"
gen="$root/bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks.dll"

run() { # name file extra-args...
  local name="$1" file="$2"; shift 2
  local out="$work/out-$name"
  rm -rf "$out"
  /usr/bin/time -v -o "$work/time.txt" dotnet "$cli" split "$file" --out "$out" "$@" >"$work/stdout.txt" 2>&1 || {
    cat "$work/stdout.txt"; return 1; }
  local bytes wall rss user sys
  bytes=$(stat -c %s "$file")
  wall=$(grep "Elapsed (wall clock)" "$work/time.txt" | awk '{print $NF}')
  rss=$(grep "Maximum resident set size" "$work/time.txt" | awk '{print $NF}')
  user=$(grep "User time" "$work/time.txt" | awk '{print $NF}')
  sys=$(grep "System time" "$work/time.txt" | awk '{print $NF}')
  # Wall MB/s is what the goal names; on a shared machine it mostly measures the queue for a CPU, so the CPU
  # time (user + sys) and the load average are printed too.
  python3 - "$name" "$bytes" "$wall" "$rss" "$user" "$sys" "$(tail -2 "$work/stdout.txt" | head -1)" "$(cut -d' ' -f1 /proc/loadavg)" <<'PY'
import sys
name, size, wall, rss, user, sys_, summary, load = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6]), sys.argv[7], sys.argv[8]
parts = [float(p) for p in wall.split(":")]
secs = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
cpu = user + sys_
print(f"{name:<26} {size/1e6:7.1f} MB wall {secs:7.2f} s {size/1e6/secs:7.1f} MB/s | cpu {cpu:6.2f} s (user {user:.2f} sys {sys_:.2f}) {size/1e6/cpu:6.1f} MB/cpu-s | peak RSS {rss/1024:5.1f} MB | load {load} | {summary}")
PY
  rm -rf "$out"
}

dotnet "$gen" gen-surfacing "$work/1m.nc" 1000000 >/dev/null
run "1M lines, split only" "$work/1m.nc" --force
run "1M lines, check + split" "$work/1m.nc"
rm -f "$work/1m.nc"

dotnet "$gen" gen-surfacing "$work/big.nc" "$big_lines" >/dev/null
run "~1 GB, split only" "$work/big.nc" --force
run "~1 GB, check + split" "$work/big.nc"
