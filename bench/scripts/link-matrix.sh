#!/usr/bin/env bash
# The no-outage matrix of issue 28: link-faults.sh with the link never taken down (DOWN_FOR=0), for each loss and seed,
# every strategy at every rate; then one row per strategy, rate and loss: the most underruns of one run, their sum, and
# the least lead the host saw (seconds of motion ahead while it still had lines to send). A block lost, repeated or
# reordered in any run fails it (exit 1), as in link-faults.sh.
#
# Needs what link-faults.sh needs (root, ip, /dev/net/tun, python3). Usage: sudo bench/scripts/link-matrix.sh
# Environment (defaults): STRATEGIES="full chunk adaptive" RATES="1000 5000 10000" LOSSES="0 0.01 0.03" SEEDS="1 2 3 4 5 6
#   7 8 9 10" BLOCKS=20000, and the rest of link-faults.sh's (DELAY_MS, JITTER_MS, REORDER, PMACSTREAM_CLI...). The full
#   matrix is 270 runs of 5-25 s each, about an hour and a half: a subset is e.g. SEEDS=1 BLOCKS=8000.
set -euo pipefail
cd "$(dirname "$0")/../.."
STRATEGIES="${STRATEGIES:-full chunk adaptive}"
RATES="${RATES:-1000 5000 10000}"
LOSSES="${LOSSES:-0 0.01 0.03}"
SEEDS="${SEEDS:-1 2 3 4 5 6 7 8 9 10}"
export BLOCKS="${BLOCKS:-20000}" DOWN_FOR=0

if [ -z "${PMACSTREAM_CLI:-}" ]; then
  dotnet build src/PmacStream.Cli -c Release -v q -nologo >/dev/null || { echo "link-matrix: BUILD FAILED"; exit 3; }
  export PMACSTREAM_CLI="$PWD/src/PmacStream.Cli/bin/Release/net10.0/pmacstream.dll"
fi

out=$(mktemp /tmp/pmacstream-linkmatrix.XXXXXX)
failed=0
for loss in $LOSSES; do
  for seed in $SEEDS; do
    # One result line per run, tagged with its loss; link-faults.sh's own verdict decides failure.
    LOSS=$loss SEED=$seed STRATEGIES="$STRATEGIES" RATES="$RATES" bench/scripts/link-faults.sh | tee -a /dev/stderr \
      | awk -v loss="$loss" '/blocks\/s/ { print loss, $0 }' >>"$out" || failed=1
  done
done

echo
echo "load average at the end: $(cut -d" " -f1-3 /proc/loadavg) on $(nproc) cores (a starved simulator process counts as underruns too)"
echo "no outage, ${DELAY_MS:-2} ms +- ${JITTER_MS:-1} ms each way, reorder ${REORDER:-0.05}, seeds: $SEEDS, $BLOCKS blocks a run"
python3 - "$out" <<'PY'
import re, sys
rows = {}
for line in open(sys.argv[1]):
    f = line.split()
    loss, strategy, rate = f[0], f[1], int(f[2])
    m = re.search(r"underruns\s+(\S+)\s+worst lead\s+(\S+)\s+s", line)
    under = int(m.group(1)) if m and m.group(1).isdigit() else None
    lead = float(m.group(2)) if m and m.group(2) != "?" else None
    r = rows.setdefault((strategy, rate, loss), {"runs": 0, "max": 0, "sum": 0, "lead": None, "broken": 0})
    r["runs"] += 1
    if under is not None:
        r["max"] = max(r["max"], under); r["sum"] += under
    if lead is not None:
        r["lead"] = lead if r["lead"] is None else min(r["lead"], lead)
    r["broken"] += "BROKEN" in line
print("| strategy | blocks/s | loss | runs | underruns (most in a run) | underruns (sum) | worst lead s | broken |")
print("|---|---:|---:|---:|---:|---:|---:|---:|")
for (s, rate, loss), r in sorted(rows.items(), key=lambda kv: (kv[0][0], kv[0][1], float(kv[0][2]))):
    lead = "%.3f" % r["lead"] if r["lead"] is not None else "?"
    print(f"| {s} | {rate} | {float(loss)*100:g} % | {r['runs']} | {r['max']} | {r['sum']} | {lead} | {r['broken']} |")
PY
rm -f "$out"
exit "$failed"
