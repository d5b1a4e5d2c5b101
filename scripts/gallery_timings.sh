#!/usr/bin/env bash
# The gallery's speed table: every example in examples/*.toml run headless on 1 and 2 threads,
# its wall time per simulated second written into docs/gallery.md (between its timing markers;
# the thumbnails are left alone) and docs/gallery/timings.csv.
# Usage: scripts/gallery_timings.sh [--md FILE] [--csv FILE]
# MAILLE_PRESET picks the build (default release); MAILLE_NO_BUILD=1 uses the build as it is.
set -euo pipefail
cd "$(dirname "$0")/.."
md=docs/gallery.md csv=docs/gallery/timings.csv
while [ $# -gt 0 ]; do
  case $1 in
    --md) md=$2; shift ;;
    --csv) csv=$2; shift ;;
    *) echo "usage: scripts/gallery_timings.sh [--md FILE] [--csv FILE]" >&2; exit 2 ;;
  esac
  shift
done
preset=${MAILLE_PRESET:-release}
if [ -z "${MAILLE_NO_BUILD:-}" ]; then
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" --target maille
fi
export OMP_WAIT_POLICY=passive
exec /usr/bin/python3 scripts/report/gallery_timings.py --maille "build/$preset/apps/maille/maille" \
  --md "$md" --csv "$csv" --preset "$preset"
