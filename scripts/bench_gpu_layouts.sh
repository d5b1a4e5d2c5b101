#!/usr/bin/env bash
# The GPU backend's two layouts for grid cloth (docs/gpu.md, "The structured layout"):
# particle-steps per second of a square flag in gusty wind (bench/scenes/gpu_flag.toml,
# without self-collision: the link forces are what the layouts change) at N x N particles, with
# MAILLE_GPU_LAYOUT=general and =structured, in alternating rounds (the fastest round of each is
# kept: a shared machine's noise lands on both). One CSV:
#   size,particles,layout,steps,seconds,particle_steps_per_second,ns_per_particle_step,
#   status,device
# status: ok, or why the run did not happen (a refusal names the limit); device: the GPU
# driver's renderer string (commas dropped). On Mesa's llvmpipe (no GPU) the figures measure
# the software driver, not a GPU: the correctness path.
#
# Usage: scripts/bench_gpu_layouts.sh [--sizes 64,128,256] [--steps N] [--rounds R]
#                                     [--out FILE] [--gpu-device N] [--maille PATH]
# --steps default: about 1e8 particle-steps per run, within [20, 2000], after 5 untimed
# warm-up steps; --rounds default 2. --out -: the CSV to stdout only.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/gpu_bench_common.sh
sizes=64,128,256
steps=
rounds=2
out=bench/results/gpu-layouts.csv
usage="usage: $0 [--sizes 64,128] [--steps N] [--rounds R] [--out FILE] [--gpu-device N] [--maille PATH]"
gpu_bench_options "$@"
gpu_bench_build_maille
gpu_name=$(gpu_bench_gpu_name)
tmp=$(mktemp)
trap 'rm -f "$tmp" "$tmp.err" "$tmp.rows"' EXIT
: >"$tmp.rows"
IFS=, read -r -a size_list <<<"$sizes"
for ((round = 1; round <= rounds; round++)); do
  for n in "${size_list[@]}"; do
    particles=$((n * n))
    s=${steps:-$((100000000 / particles))}
    if [ -z "$steps" ]; then
      [ "$s" -gt 2000 ] && s=2000
      [ "$s" -lt 20 ] && s=20
    fi
    mass=$(awk -v p="$particles" 'BEGIN { printf "%.6g", p * 0.0005 }')
    for layout in general structured; do
      args=(bench bench/scenes/gpu_flag.toml --steps "$s" --warmup 5 --repeat 1 --no-header
            --no-self-collision --backend gpu "${device[@]}"
            --set "flag[0].resolution=[$n,$n]" --set "flag[0].mass=$mass")
      if row=$(MAILLE_GPU_LAYOUT=$layout "$maille" "${args[@]}" 2>"$tmp.err"); then
        # scene,points,links,threads,steps,seconds,ns_per_particle_step,backend,pps,...
        IFS=, read -r _ points _ _ nsteps seconds ns _ pps _ <<<"$row"
        echo "$n,$points,$layout,$nsteps,$seconds,$pps,$ns,ok,$gpu_name" >>"$tmp.rows"
      else
        why=$(tr '\n,' '  ' <"$tmp.err" | sed 's/ *$//')
        echo "$n,$particles,$layout,$s,,,,${why:-failed},$gpu_name" >>"$tmp.rows"
      fi
      echo "round $round N=$n $layout: $(tail -1 "$tmp.rows")" >&2
    done
  done
done
# The fastest round of each size and layout (a failed run has no time: it is kept only when
# every round failed).
echo "size,particles,layout,steps,seconds,particle_steps_per_second,ns_per_particle_step,status,device" >"$tmp"
for n in "${size_list[@]}"; do
  for layout in general structured; do
    best=$(awk -F, -v n="$n" -v l="$layout" '$1 == n && $3 == l && $8 == "ok" { print }' \
             "$tmp.rows" | sort -t, -k7,7g | head -1)
    [ -n "$best" ] || best=$(awk -F, -v n="$n" -v l="$layout" '$1 == n && $3 == l' "$tmp.rows" |
                               head -1)
    echo "$best" >>"$tmp"
  done
done
if [ "$out" = - ]; then
  cat "$tmp"
else
  mkdir -p "$(dirname "$out")"
  cp "$tmp" "$out"
  cat "$tmp"
  echo "wrote $out"
fi
