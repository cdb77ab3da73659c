#!/usr/bin/env bash
# Runs the simulator's fuzz targets (the VR_PMAC packet parser, the ASCII command parser, the serial line) for
# longer than CI does and from fresh seeds. CI runs the same tests for 4 s each from fixed seeds.
# Usage: bench/scripts/fuzz.sh [SECONDS_PER_TARGET] [ROUNDS]   (defaults 60 and 1; each round takes a new seed)
# A failure prints the seed and the input; PMACSTREAM_FUZZ_SEED=N repeats a round.
set -euo pipefail
cd "$(dirname "$0")/../.."
SECONDS_PER_TARGET="${1:-60}"
ROUNDS="${2:-1}"
dotnet build tests/PmacStream.Sim.Tests -c Release -v q -nologo >/dev/null
for round in $(seq 1 "$ROUNDS"); do
  seed="${PMACSTREAM_FUZZ_SEED:-$(( (RANDOM << 15) | RANDOM ))}"
  echo "== round $round: seed $seed, $SECONDS_PER_TARGET s per target"
  PMACSTREAM_FUZZ_SECONDS="$SECONDS_PER_TARGET" PMACSTREAM_FUZZ_SEED="$seed" \
    dotnet test tests/PmacStream.Sim.Tests -c Release --no-build --filter "FullyQualifiedName~PmacStream.Sim.Tests.Fuzz" \
      --logger "console;verbosity=detailed" 2>&1 | grep -E "seed [0-9]+:|\[FAIL\]|Error Message|Expected|Stack overflow|Passed!|Failed!|aborted" || true
done
