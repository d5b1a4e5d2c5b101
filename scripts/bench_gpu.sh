#!/usr/bin/env bash
# The CPU/GPU table: particle-steps per second of a square flag in gusty wind
# (bench/scenes/gpu_flag.toml) at N x N particles, on the CPU with one thread, the CPU with all
# threads and the GPU backend, with and without self-collision, as one CSV:
#   size,particles,config,self_collision,threads,steps,seconds,particle_steps_per_second,
#   ns_per_particle_step,status,device
# config: cpu1 | cpuall | gpu; status: ok, or why the run did not happen (a refusal names the
# stage or the limit); device: the CPU's model, or the GPU driver's renderer string (commas
# dropped), so that every figure carries the device that made it. Every size runs the same step and particle mass (the scene's comment).
#
# Usage: scripts/bench_gpu.sh [--sizes 64,256,1024,2048] [--steps N] [--out FILE]
#                             [--gpu-device N] [--maille PATH]
# Default sizes: 64,256,1024,2048 (on a real GPU); Mesa's llvmpipe (no GPU) gets through 256 in
# minutes, and refuses sizes whose buffers exceed its 128 MiB storage blocks. --steps default:
# enough for about 2e7 particle-steps per run (at least 3), after 2 untimed warm-up steps.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/gpu_bench_common.sh
sizes=64,256,1024,2048
steps=
out=bench/results/gpu-flags.csv
usage="usage: $0 [--sizes 64,256] [--steps N] [--out FILE] [--gpu-device N] [--maille PATH]"
gpu_bench_options "$@"
gpu_bench_build_maille
unset OMP_WAIT_POLICY  # benchmarks run alone: spinning OpenMP threads are right (scripts/bench.sh)
cores=$(nproc)
cpu_name=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//; s/,//g')
gpu_name=$(gpu_bench_gpu_name)
mkdir -p "$(dirname "$out")"
tmp=$(mktemp)
trap 'rm -f "$tmp" "$tmp.err"' EXIT
echo "size,particles,config,self_collision,threads,steps,seconds,particle_steps_per_second,ns_per_particle_step,status,device" >"$tmp"
IFS=, read -r -a size_list <<<"$sizes"
for n in "${size_list[@]}"; do
  particles=$((n * n))
  s=${steps:-$(( 20000000 / particles > 3 ? 20000000 / particles : 3 ))}
  [ "$s" -gt 2000 ] && s=2000
  mass=$(awk -v p="$particles" 'BEGIN { printf "%.6g", p * 0.0005 }')
  for sc in on off; do
    for config in cpu1 cpuall gpu; do
      args=(bench bench/scenes/gpu_flag.toml --steps "$s" --warmup 2 --repeat 2 --no-header
            --set "flag[0].resolution=[$n,$n]" --set "flag[0].mass=$mass")
      [ "$sc" = off ] && args+=(--no-self-collision)
      case $config in
        cpu1) args+=(--backend cpu --threads 1) ;;
        cpuall) args+=(--backend cpu --threads "$cores") ;;
        gpu) args+=(--backend gpu "${device[@]}") ;;
      esac
      name=$cpu_name
      [ "$config" = gpu ] && name=$gpu_name
      if row=$("$maille" "${args[@]}" 2>"$tmp.err"); then
        # scene,points,links,threads,steps,seconds,ns_per_particle_step,backend,pps,...
        IFS=, read -r _ points _ threads nsteps seconds ns _ pps _ <<<"$row"
        echo "$n,$points,$config,$sc,$threads,$nsteps,$seconds,$pps,$ns,ok,$name" >>"$tmp"
      else
        why=$(tr '\n,' '  ' <"$tmp.err" | sed 's/ *$//')
        echo "$n,$particles,$config,$sc,,$s,,,,${why:-failed},$name" >>"$tmp"
      fi
      echo "N=$n $config self_collision=$sc: $(tail -1 "$tmp")" >&2
    done
  done
done
mv "$tmp" "$out"
trap - EXIT
echo "wrote $out"
