#!/usr/bin/env bash
# Publishes the CLI as a Native AOT binary (no JIT, no start-up compile): the fast way to run `pmacstream check`.
# Usage: bench/scripts/publish-aot.sh [OUT_DIR]   (default: artifacts/aot/linux-x64)
# Prints the path of the binary (last line of stdout). Warnings are errors here too.
# Extra dotnet publish arguments can be passed in $AOT_ARGS (e.g. AOT_ARGS="-p:IlcInstructionSet=native").
set -euo pipefail
cd "$(dirname "$0")/../.."
RID=${RID:-linux-x64}
OUT=${1:-artifacts/aot/$RID}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
# shellcheck disable=SC2086
dotnet publish src/PmacStream.Cli -c Release -r "$RID" -p:PublishAot=true -o "$OUT" -v q -nologo ${AOT_ARGS:-} >&2
echo "$OUT/pmacstream"
