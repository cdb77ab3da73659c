#!/usr/bin/env bash
# The HMI's toolpath pane on a large program (issue 18): time to the first picture of the planned toolpath, the
# executed trace through the whole program (UI time per tick) and peak memory, through the presenter as the form
# drives it. The program is generated into a temporary folder and deleted afterwards.
#
#   bench/scripts/toolpath-pane-bench.sh [LINES] [LINES_PER_TICK]      default 10000000 lines, M0 200000 lines a tick
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$ROOT"
dotnet build -c Release bench/PmacStream.Benchmarks -nologo -v q >/dev/null
dotnet bench/PmacStream.Benchmarks/bin/Release/net10.0/PmacStream.Benchmarks.dll hmi-toolpath "${1:-10000000}" "${2:-200000}"
