#!/usr/bin/env bash
# Implicit Euler by vertex block descent on the GPU against the CPU (one thread), two scenes at
# 64 x 64 and 128 x 128, h = 1/60 s, 10 sweeps, acceleration 0.9, coarse = "off":
#   flag    a square flag in gusty wind without self-collision (bench/scenes/gpu_flag.toml,
#           0.5 g per particle)
#   sphere  the peer scene: a 1 m cloth (0.3 kg) dropped on a geometric sphere, its contacts
#           inside the solve (bench/scenes/gpu_cloth_on_sphere.toml); the timed second is the
#           fall, the impact and the draping
# One CSV row per run:
#   scene,size,backend,wall_s_per_simulated_s,solver_iterations,solver_residual,device
# wall time from `maille bench` (60 steps = 1 simulated second, after 2 untimed steps);
# iterations and residual from the last row of stats.csv of a 30-step `maille run` (sampled
# every 10 steps). Finishes in well under two minutes on a machine with a real GPU.
#
# Usage: scripts/device_vbd_check.sh PATH/TO/maille [--sizes 64,128] [--gpu-device N]
# The device column names the GPU's renderer (`maille info --backend gpu`) or the CPU's model.
set -euo pipefail
if [ $# -lt 1 ]; then
  echo "usage: $0 PATH/TO/maille [--sizes 64,128] [--gpu-device N]" >&2
  exit 2
fi
maille=$(realpath "$1")
shift
sizes=64,128
device=()
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) sizes=$2; shift 2 ;;
    --gpu-device) device=(--gpu-device "$2"); shift 2 ;;
    *) echo "usage: $0 PATH/TO/maille [--sizes 64,128] [--gpu-device N]" >&2; exit 2 ;;
  esac
done
cd "$(dirname "$0")/.."
unset OMP_WAIT_POLICY
h=0.016666666666666666
steps=60
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# Without --gpu-device: the first EGL device that is not a software one (the NVIDIA driver's
# GPUs are EGL devices; the default surfaceless platform may be Mesa's llvmpipe), else the default.
if [ ${#device[@]} -eq 0 ]; then
  hardware=$("$maille" info --backend gpu 2>/dev/null |
    sed -n 's/^ *\([0-9][0-9]*\): .*$/&/p' | grep -v -i software | head -1 |
    sed 's/^ *\([0-9][0-9]*\):.*/\1/' || true)
  [ -n "$hardware" ] && device=(--gpu-device "$hardware")
fi
cpu_name=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//; s/,//g')
gpu_name=$("$maille" info --backend gpu "${device[@]}" 2>/dev/null | sed -n 's/^renderer *//p' |
  tr -d ',' || true)
echo "scene,size,backend,wall_s_per_simulated_s,solver_iterations,solver_residual,device"
IFS=, read -r -a size_list <<<"$sizes"
for scene in flag sphere; do
for n in "${size_list[@]}"; do
  if [ "$scene" = flag ]; then
    file=bench/scenes/gpu_flag.toml
    mass=$(awk -v p="$((n * n))" 'BEGIN { printf "%.6g", p * 0.0005 }')
  else
    file=bench/scenes/gpu_cloth_on_sphere.toml
    mass=0.3
  fi
  sets=(--set "flag[0].resolution=[$n,$n]" --set "flag[0].mass=$mass"
        --set "simulation.step=$h" --set 'simulation.integrator="implicit_euler"'
        --set 'simulation.implicit.solver="vbd"' --set simulation.implicit.iterations=10
        --set simulation.implicit.acceleration=0.9 --set 'simulation.implicit.coarse="off"'
        --no-self-collision)
  for backend in gpu cpu; do
    if [ "$backend" = gpu ]; then
      where=(--backend gpu "${device[@]}")
      name=${gpu_name:-unavailable}
    else
      where=(--backend cpu --threads 1)
      name=$cpu_name
    fi
    if ! row=$("$maille" bench "$file" --steps "$steps" --warmup 2 --repeat 1 \
        --no-header "${sets[@]}" "${where[@]}" 2>"$tmp/err"); then
      echo "$scene,$n,$backend,,,,$(tr '\n,' '  ' <"$tmp/err")"
      continue
    fi
    # scene,points,links,threads,steps,seconds,...
    IFS=, read -r _ _ _ _ nsteps seconds _ <<<"$row"
    wall=$(awk -v s="$seconds" -v k="$nsteps" -v h="$h" 'BEGIN { printf "%.4g", s / (k * h) }')
    "$maille" run "$file" --steps 30 --no-frames --out "$tmp/run" \
      --set simulation.sample_every=10 "${sets[@]}" "${where[@]}" >/dev/null 2>"$tmp/err"
    stats=$tmp/run/stats.csv
    col() { awk -F, -v c="$1" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == c) k = i }
                                 END { if (k) print $k }' "$stats"; }
    echo "$scene,$n,$backend,$wall,$(col solver_iterations),$(col solver_residual),$name"
  done
done
done
