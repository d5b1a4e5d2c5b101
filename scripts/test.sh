#!/usr/bin/env bash
# One command: install what is missing, build (release, warnings as errors), run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export OMP_WAIT_POLICY=passive  # spin-waiting threads starve a busy 2-core machine
cmake --preset release >/dev/null
cmake --build --preset release
ctest --preset release
