#!/usr/bin/env bash
# One command: install what is missing, build (release), run every test.
# MAILLE_PRESET picks the CMake preset: `release` (default: optimised for this CPU, warnings
# shown but not fatal), `portable` (any x86-64), `dev` (warnings as errors: what CI uses).
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${MAILLE_PRESET:-release}
scripts/setup.sh
export OMP_WAIT_POLICY=passive  # spin-waiting threads starve a busy 2-core machine
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset"
