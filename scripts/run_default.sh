#!/usr/bin/env bash
# One command: install what is missing, build (release), run the default scene (the flag in
# wind) headless. Frames and stats.csv go to out/flag_in_wind/; a summary is printed.
# Extra arguments go to `maille run` (e.g. --duration 2 --format vtk).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target maille
exec build/release/apps/maille/maille run examples/flag_in_wind.toml "$@"
