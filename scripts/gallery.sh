#!/usr/bin/env bash
# The gallery: every example in examples/*.toml rendered headless by `maille render` to a
# thumbnail, and the page that shows them with the command that reproduces each.
# Usage: scripts/gallery.sh [--quick] [--out DIR] [--only NAME[,NAME...]]
#   default  320 x 180 thumbnails in docs/gallery/, the page docs/gallery.md
#   --quick  160 x 90 at t = 0.1 s in out/gallery-quick/ (page: out/gallery-quick/gallery.md):
#            a check that every scene renders, for CI; the committed gallery is left alone
#   --out D  thumbnails in D/gallery/, the page D/gallery.md
#   --only N render only these scenes (comma-separated names, e.g. a new example's): the other
#            scenes keep the thumbnails already there, and the page lists every scene
# MAILLE_PRESET picks the build (default release); MAILLE_NO_BUILD=1 uses the build as it is
# (scripts/report.sh has just built it).
set -euo pipefail
cd "$(dirname "$0")/.."
quick=() out= only=()
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=(--quick) ;;
    --out) out=$2; shift ;;
    --only) only=(--only "$2"); shift ;;
    *) echo "usage: scripts/gallery.sh [--quick] [--out DIR] [--only NAME[,NAME...]]" >&2; exit 2 ;;
  esac
  shift
done
preset=${MAILLE_PRESET:-release}
if [ -z "${MAILLE_NO_BUILD:-}" ]; then
  scripts/setup.sh python3-matplotlib
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" --target maille
fi
maille=build/$preset/apps/maille/maille
if ! "$maille" render --help 2>&1 | grep -q -- '--fps'; then  # (--help alone exits 0 without it)
  echo "gallery: $maille has no render command (configured with MAILLE_BUILD_RENDER=OFF?)" >&2
  exit 1
fi
if [ -n "$out" ]; then
  pngs=$out/gallery md=$out/gallery.md
elif [ ${#quick[@]} -gt 0 ]; then
  pngs=out/gallery-quick md=out/gallery-quick/gallery.md
else
  pngs=docs/gallery md=docs/gallery.md
fi
export OMP_WAIT_POLICY=passive
exec /usr/bin/python3 scripts/report/gallery.py --maille "$maille" --out "$pngs" --md "$md" \
  "${quick[@]}" "${only[@]}"
