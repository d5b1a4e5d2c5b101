#!/usr/bin/env bash
# The offline sound targets in one run (docs/sound.md, "A lean step"): `maille run --audio
# --no-frames --threads 1` of examples/sound_drum.toml (target: 4x real time) and
# examples/sound_plucked_string.toml (25x), as simulated seconds per second of the process's CPU
# time (user + system: a shared machine inflates wall time, which is shown too), and the same
# for a BASE build when given (the ratio of the two, measured side by side, is the change's).
#   scripts/sound_targets.sh [BUILD_DIR] [BASE_MAILLE]     (default build/release; 3 runs each,
#                                                          the fastest kept)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build=${1:-build/release}
base=${2:-}
export OMP_WAIT_POLICY=passive
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# binary scene seconds: the fastest of three runs, "cpu_s wall_s"
best() {
  local b=$1 scene=$2 secs=$3 i line bestc=1e9 bestw=1e9
  for i in 1 2 3; do
    line=$( { /usr/bin/time -f "%U %S %e" "$b" run "$here/examples/$scene.toml" --audio "$tmp/a.wav" \
               --no-frames --threads 1 --duration "$secs" --out "$tmp/out" >/dev/null; } 2>&1 | tail -1)
    read -r u s w <<<"$line"
    bestc=$(python3 -c "print(round(min($bestc, $u + $s), 2))")
    bestw=$(python3 -c "print(min($bestw, $w))")
  done
  echo "$bestc $bestw"
}
echo "scene,simulated_s,build,cpu_s,wall_s,realtime_x_cpu,realtime_x_wall"
for pair in "sound_drum 1" "sound_plucked_string 6"; do
  read -r scene secs <<<"$pair"
  for which in new base; do
    b="$build/apps/maille/maille"
    if [ "$which" = base ]; then [ -n "$base" ] || continue; b=$base; fi
    read -r c w <<<"$(best "$b" "$scene" "$secs")"
    echo "$scene,$secs,$which,$c,$w,$(python3 -c "print(f'{$secs / $c:.2f},{$secs / $w:.2f}')")"
  done
done
