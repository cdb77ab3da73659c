#!/usr/bin/env bash
# Runs the fuzz targets for longer than CI does and from fresh seeds: the simulator's (the VR_PMAC packet parser, the
# ASCII command parser, the serial line) and the lexer's, checker's and splitter's (tests/PmacStream.Core.Tests/Fuzz:
# seeded and mutated programs, the lane against the full path, nothing split that the check refuses). CI runs the same
# tests for 4 s each from fixed seeds.
# Usage: bench/scripts/fuzz.sh [SECONDS_PER_TARGET] [ROUNDS]   (defaults 60 and 1; each round takes a new seed)
# A failure prints the seed and the input (a G-code input is kept as /tmp/pmacstream-fuzz-SEED-N.nc);
# PMACSTREAM_FUZZ_SEED=N repeats a round. TARGETS="sim core" picks the projects.
set -euo pipefail
cd "$(dirname "$0")/../.."
SECONDS_PER_TARGET="${1:-60}"
ROUNDS="${2:-1}"
TARGETS="${TARGETS:-sim core}"
declare -A PROJECT=([sim]=PmacStream.Sim.Tests [core]=PmacStream.Core.Tests)
for t in $TARGETS; do dotnet build "tests/${PROJECT[$t]}" -c Release -v q -nologo >/dev/null; done
for round in $(seq 1 "$ROUNDS"); do
  seed="${PMACSTREAM_FUZZ_SEED:-$(( (RANDOM << 15) | RANDOM ))}"
  echo "== round $round: seed $seed, $SECONDS_PER_TARGET s per target"
  for t in $TARGETS; do
    PMACSTREAM_FUZZ_SECONDS="$SECONDS_PER_TARGET" PMACSTREAM_FUZZ_SEED="$seed" \
      dotnet test "tests/${PROJECT[$t]}" -c Release --no-build --filter "FullyQualifiedName~${PROJECT[$t]}.Fuzz" \
        --logger "console;verbosity=detailed" 2>&1 | grep -E "seed [0-9]+:|\[FAIL\]|Error Message|Expected|Stack overflow|Passed!|Failed!|aborted" || true
  done
done
