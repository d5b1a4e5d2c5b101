#!/usr/bin/env bash
# The live period budget (docs/sound.md "Playing live", "Period budget"): `maille play
# --benchmark` on the playable drum at growing sizes, one and two threads, 48 kHz, 64-frame
# periods: the step's CPU time per period (CLOCK_THREAD_CPUTIME_ID), mean and 99th percentile,
# as a fraction of the period. The drum's total mass grows with its points so that every size has
# the same bead, hence the same stability limit and the same tension range.
#   scripts/bench_play.sh [BUILD_DIR] [RINGS...]     (default build/release; rings 8 12 14 18 22 26)
set -euo pipefail
build=${1:-build/release}
shift || true
rings=("$@")
[ ${#rings[@]} -eq 0 ] && rings=(8 12 14 18 22 26)
maille="$build/apps/maille/maille"
scene="$(dirname "$0")/../examples/play_drum.toml"
export OMP_WAIT_POLICY=passive
echo "rings,points,threads,cpu_mean,cpu_p99,cpu_largest,wall_mean,wall_p99"
for r in "${rings[@]}"; do
  # The listened and struck point in the middle of the membrane's list (inside the rim), the
  # mass scaled with the area to keep play_drum's bead (rings 14: 0.05 kg).
  half=$(((3 * r * (r + 1) + 1) / 2))
  sets=(--set "membrane[0].rings=$r" --set "listen[0].point=skin:$half"
        --set "control[0].excite.point=skin:$half" --set "membrane[0].mass=$(python3 -c "print(0.05 * $r * $r / 196)")")
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
