#!/usr/bin/env bash
# The speed-up of `maille sweep` from 1 to 2 ranks (docs/sweep.md, "What scales"): 8 cases of
# the default flag (600 points, 4 simulated seconds each, one thread per case), run REPEAT times
# (default 3) in one process without mpirun, under `mpirun -n 1` and under `mpirun -n 2`. Prints
# a CSV row per run (wall time measured around the command: mpirun's start included) and the
# speed-up of the fastest runs. The summaries of every run must agree (sweep_compare.py).
#
#   scripts/sweep_speedup.sh [MAILLE] [OUT]     (defaults: build/release/apps/maille/maille,
#                                                out/sweep_speedup)
# MPIRUN_ARGS adds options to mpirun, e.g. MPIRUN_ARGS="--bind-to none" (on a machine shared
# with other work, a rank pinned to a busy core cannot move to the idle one).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
maille=${1:-$here/build/release/apps/maille/maille}
out=${2:-$here/out/sweep_speedup}
repeat=${REPEAT:-3}
mpirun=(mpirun --allow-run-as-root --oversubscribe ${MPIRUN_ARGS:-})
export OMP_WAIT_POLICY=passive
rm -rf "$out"
mkdir -p "$out"
cat >"$out/speedup.toml" <<EOF
scene = "$here/examples/flag_in_wind.toml"
duration = 4.0
[axes]
"flag[0].stiffness" = [150.0, 200.0, 250.0, 300.0, 350.0, 400.0, 450.0, 500.0]
EOF
now() { date +%s.%N; }
calc() { awk "BEGIN { print ($1) }"; }
echo "ranks,launcher,run,wall_seconds,cpu_seconds"
declare -A best
for r in $(seq "$repeat"); do
  for how in one mpirun1 mpirun2; do
    case $how in
      one) cmd=("$maille") ranks=1 ;;
      mpirun1) cmd=("${mpirun[@]}" -n 1 "$maille") ranks=1 ;;
      mpirun2) cmd=("${mpirun[@]}" -n 2 "$maille") ranks=2 ;;
    esac
    dir=$out/$how-$r
    t0=$(now)
    cpu0=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
    "${cmd[@]}" sweep "$out/speedup.toml" --out "$dir" --threads 1 >"$dir.log" 2>&1
    t1=$(now)
    cpu1=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
    wall=$(calc "$t1 - $t0")
    cpu=$(calc "($cpu1 - $cpu0) / $(getconf CLK_TCK)")
    printf '%d,%s,%d,%.3f,%.2f\n' "$ranks" "$how" "$r" "$wall" "$cpu"
    /usr/bin/python3 "$here/tests/sweep_compare.py" "$out/one-1/summary.csv" "$dir/summary.csv" \
      >/dev/null
    if [ -z "${best[$how]:-}" ] || [ "$(calc "$wall < ${best[$how]}")" = 1 ]; then
      best[$how]=$wall
    fi
  done
done
printf 'best: one process %.3f s, mpirun -n 1 %.3f s, mpirun -n 2 %.3f s; speed-up 1 -> 2 ranks: %.2f (against one process), %.2f (against mpirun -n 1); load average now: %s\n' \
  "${best[one]}" "${best[mpirun1]}" "${best[mpirun2]}" \
  "$(calc "${best[one]} / ${best[mpirun2]}")" \
  "$(calc "${best[mpirun1]} / ${best[mpirun2]}")" "$(cut -d' ' -f1-3 /proc/loadavg)"
