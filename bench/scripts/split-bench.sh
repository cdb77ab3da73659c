#!/usr/bin/env bash
# Whole-process benchmark of `pmacstream split` (issue 4): MB/s and peak RSS on the 1,000,000-line generated
# surfacing program and on a ~1 GB one. Goals: >= 300 MB/s, <= 64 MB peak RSS (whole process).
# Usage: [RUNS=3] [OUT_ROOT=DIR] bench/scripts/split-bench.sh [WORKDIR] [BIG_LINES]
#   RUNS: how many times each configuration runs (default 3). Wall time on a shared VM swings by about 25 % from one
#   minute to the next, so the summary at the end gives the best and the median run of each configuration.
#   OUT_ROOT: where the chunk folders go (default WORKDIR). OUT_ROOT=/dev/shm measures the program with a file system
#   whose create cost does not depend on what was deleted minutes ago (see below); the sources stay in WORKDIR.
#   DELETE_EACH=1: delete each run's chunk folder once it is measured (default: all at the end, which ext4 needs, see
#   below). Use it with OUT_ROOT=/dev/shm: keeping 6 x 1.5 GB of chunks in RAM made later runs on this VM spend 6 s
#   instead of 1.5 s in the kernel (memory reclaim: the VM runs DAMON's kdamond), whatever the program did.
#   Before each run, `sync` writes back what earlier runs left dirty, so no run pays for another's write-back.
#   PMACSTREAM_CLI=/path/to/pmacstream (e.g. a Native AOT publish) runs that binary instead of `dotnet pmacstream.dll`.
# Each file is split twice: `--force` (no checker) and the default (checker and splitter in ONE streamed pass).
# Every run writes its own output folder and all are deleted only at the end. Why: ext4 avoids reusing inodes freed
# in the last 60 s (360 s while their inode-table block is dirty) and scans past every one of them on each create
# (kernel recently_deleted()/find_inode_bit() in `perf`), so creating 30,000 files minutes after ANY process deleted
# many files on the same file system costs seconds to tens of seconds of system time (seen here: 0.3 s to 5 s for
# the same 8,000 files, 1.4 s to 21 s for 30,000). On a quiet machine, start it >= 6 minutes after large deletions
# (including a previous run's clean-up); the "fs floor" line before each run shows what creation costs right then.
# Columns: wall time and MB/s by wall (the goal's measure; on a shared machine it includes waiting for a CPU), CPU
# time (user + sys) and MB per CPU-second, peak RSS (/usr/bin/time), the 1-minute load average before and after.
# "fs floor" is the time a trivial writer needs to create the same number of files of the same total size in the
# same file system just before the runs of each size: what file creation alone costs there at that moment. It can
# also take the whole slow-create cost itself (it allocates past the recently freed inodes first: seen 19 s for the
# floor, then 1.7 s of system time for the split right after), so read it together with the runs' sys time.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="${1:-$(mktemp -d /tmp/pmacstream-split-bench.XXXXXX)}"
big_lines="${2:-29800000}"   # ~36 bytes a line: ~1.07 GB
mkdir -p "$work"
trap 'rm -rf "$work"' EXIT

dotnet build -c Release "$root/src/PmacStream.Cli" -v q -nologo >/dev/null
dotnet build -c Release "$root/bench/PmacStream.Benchmarks" -v q -nologo >/dev/null
if [[ -n "${PMACSTREAM_CLI:-}" ]]; then cli=("$PMACSTREAM_CLI"); else cli=(dotnet "$root/src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll"); fi
gen="$root/bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks.dll"
echo "split-bench: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), cli: ${cli[*]}"

floor() { # name count total-bytes: create count files totalling bytes, print wall and sys
  python3 - "$out_base/floor-${1//[^a-zA-Z0-9]/_}" "$2" "$3" <<'PY'
import os, sys, time
d, n, total = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
os.makedirs(d)
data = b"x" * max(1, total // max(1, n))
t, c = time.time(), os.times()
for i in range(n):
    fd = os.open(f"{d}/f_{i:05d}.pmc", os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
    os.write(fd, data)
    os.close(fd)
c2 = os.times()
print(f"|   fs floor: {n} files   |            | wall {time.time() - t:6.2f} s |              | sys {c2.system - c.system:6.2f} s")
PY
}

out_root="${OUT_ROOT:-$work}"
mkdir -p "$out_root"
out_base="$(mktemp -d "$out_root/split-bench-out.XXXXXX")"
trap 'rm -rf "$work" "$out_base"' EXIT

run() { # name file extra-args...
  local name="$1" file="$2"; shift 2
  local out="$out_base/out-${name//[^a-zA-Z0-9]/_}"
  sync
  local load0; load0=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -v -o "$work/time.txt" "${cli[@]}" split "$file" --out "$out" "$@" >"$work/stdout.txt" 2>&1 || {
    cat "$work/stdout.txt"; return 1; }
  [[ "${DELETE_EACH:-0}" == 1 ]] && rm -rf "$out"
  local bytes wall rss user sys
  bytes=$(stat -c %s "$file")
  wall=$(grep "Elapsed (wall clock)" "$work/time.txt" | awk '{print $NF}')
  rss=$(grep "Maximum resident set size" "$work/time.txt" | awk '{print $NF}')
  user=$(grep "User time" "$work/time.txt" | awk '{print $NF}')
  sys=$(grep "System time" "$work/time.txt" | awk '{print $NF}')
  python3 - "$name" "$bytes" "$wall" "$rss" "$user" "$sys" "$(grep ' chunks, ' "$work/stdout.txt" | tail -1)" "$load0" "$(cut -d' ' -f1 /proc/loadavg)" "$work/results.tsv" <<'PY'
import sys
name, size, wall, rss, user, sys_, summary, load0, load1 = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6]), sys.argv[7], sys.argv[8], sys.argv[9]
parts = [float(p) for p in wall.split(":")]
secs = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
cpu = user + sys_
print(f"| {name:<24} | {size/1e6:7.1f} MB | wall {secs:6.2f} s | {size/1e6/secs:6.1f} MB/s | cpu {cpu:6.2f} s (user {user:.2f} sys {sys_:.2f}) | {size/1e6/cpu:6.1f} MB/cpu-s | RSS {rss/1024:5.1f} MB | load {load0}->{load1} | {summary}")
with open(sys.argv[10], "a") as f:
    f.write(f"{name.split(' #')[0]}\t{size}\t{secs}\t{rss}\n")
PY
}

runs="${RUNS:-3}"
repeat() { # name file extra-args...: the configuration RUNS times
  local name="$1"; shift
  for r in $(seq 1 "$runs"); do run "$name #$r" "$@"; done
}

chunks_of() { echo $(( $(stat -c %s "$1") / 37000 + 1 )); }

dotnet "$gen" gen-surfacing "$work/1m.nc" 1000000 >/dev/null
floor 1m-force "$(chunks_of "$work/1m.nc")" "$(stat -c %s "$work/1m.nc")"
repeat "1M lines, split --force" "$work/1m.nc" --force
repeat "1M lines, check+split" "$work/1m.nc"

dotnet "$gen" gen-surfacing "$work/big.nc" "$big_lines" >/dev/null
floor big-force "$(chunks_of "$work/big.nc")" "$(stat -c %s "$work/big.nc")"
repeat "big, split --force" "$work/big.nc" --force
repeat "big, check+split" "$work/big.nc"

python3 - "$work/results.tsv" <<'PY'
import sys, statistics
rows = {}
for line in open(sys.argv[1]):
    name, size, secs, rss = line.rstrip("\n").split("\t")
    rows.setdefault(name, []).append((float(secs), int(size), int(rss)))
print("summary (best / median of each configuration):")
for name, runs in rows.items():
    secs = sorted(r[0] for r in runs)
    size = runs[0][1]
    print(f"| {name:<24} | best {secs[0]:6.2f} s {size/1e6/secs[0]:6.1f} MB/s | median {statistics.median(secs):6.2f} s {size/1e6/statistics.median(secs):6.1f} MB/s | peak RSS {max(r[2] for r in runs)/1024:5.1f} MB | {len(runs)} runs")
PY
