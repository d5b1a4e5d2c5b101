#!/usr/bin/env bash
# The live period budget (docs/sound.md "Playing live", "Period budget"): `maille play
# --benchmark` on a drum at growing sizes, one and two threads, 48 kHz, 64-frame periods: the
# step's CPU time per period (CLOCK_THREAD_CPUTIME_ID), mean and 99th percentile, as a fraction
# of the period. Every size keeps the same bead and spacing, hence the same stability limit and
# wave speed.
#   scripts/bench_play.sh [BUILD_DIR] [RINGS...]             the round drum, examples/play_drum.toml
#                                                            (default rings 8 12 14 18 22 26)
#   scripts/bench_play.sh [BUILD_DIR] --square [SIDES...]    the square drum, n x n beads with
#                                                            fixed edges (the live budget's measure;
#                                                            bench/scenes/play_square_drum.toml,
#                                                            default sides 16 24 32 40 48)
# Columns: the size (rings or side), points (all, the rim's fixed ones included), threads, then
# fractions of the period.
set -euo pipefail
build=${1:-build/release}
shift || true
shape=round
if [ "${1:-}" = --square ]; then
  shape=square
  shift
fi
sizes=("$@")
here="$(dirname "$0")/.."
if [ "$shape" = square ]; then
  [ ${#sizes[@]} -eq 0 ] && sizes=(16 24 32 40 48)
  scene="$here/bench/scenes/play_square_drum.toml"
else
  [ ${#sizes[@]} -eq 0 ] && sizes=(8 12 14 18 22 26)
  scene="$here/examples/play_drum.toml"
fi
maille="$build/apps/maille/maille"
export OMP_WAIT_POLICY=passive
echo "size,points,threads,cpu_mean,cpu_p99,cpu_largest,wall_mean,wall_p99"
for r in "${sizes[@]}"; do
  if [ "$shape" = square ]; then
    # Point (n/3, n/2) listened and struck; spacing 0.3/13 m and bead 0.05/523 kg kept.
    at=$(((r / 2) * r + r / 3))
    sets=(--set "net[0].resolution=[$r,$r]" --set "listen[0].point=skin:$at"
          --set "control[0].excite.point=skin:$at"
          --set "net[0].width=$(python3 -c "print(0.3 / 13 * ($r - 1))")"
          --set "net[0].depth=$(python3 -c "print(0.3 / 13 * ($r - 1))")"
          --set "net[0].mass=$(python3 -c "print(0.05 / 523 * $r * $r)")")
  else
    # The listened and struck point in the middle of the membrane's list (inside the rim), the
    # mass scaled with the area to keep play_drum's bead (rings 14: 0.05 kg).
    half=$(((3 * r * (r + 1) + 1) / 2))
    sets=(--set "membrane[0].rings=$r" --set "listen[0].point=skin:$half"
          --set "control[0].excite.point=skin:$half" --set "membrane[0].mass=$(python3 -c "print(0.05 * $r * $r / 196)")")
  fi
  points=$("$maille" validate "$scene" "${sets[@]}" | grep -o '([0-9]* points' | tr -dc 0-9)
  for t in 1 2; do
    line=$("$maille" play "$scene" --benchmark --duration 2 --threads "$t" "${sets[@]}")
    mean=$(grep -o 'CLOCK_THREAD_CPUTIME_ID) mean [0-9.]* %' <<<"$line" | sed 's/.*mean//' | tr -dc 0-9.)
    p99=$(grep -o 'CLOCK_THREAD_CPUTIME_ID) mean [0-9.]* %, p99 [0-9.]* %' <<<"$line" | sed 's/.*p99//' | tr -dc 0-9.)
    big=$(grep -o 'largest [0-9.]* %' <<<"$line" | tr -dc 0-9.)
    wmean=$(grep -o 'wall time mean [0-9.]* %' <<<"$line" | tr -dc 0-9.)
    wp99=$(grep -o 'wall time mean [0-9.]* %, p99 [0-9.]* %' <<<"$line" | sed 's/.*p99//' | tr -dc 0-9.)
    echo "$r,$points,$t,$(python3 -c "print(*(f'{x / 100:.3f}' for x in ($mean, $p99, $big, $wmean, $wp99)), sep=',')")"
  done
done
