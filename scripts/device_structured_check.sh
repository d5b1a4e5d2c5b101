#!/usr/bin/env bash
# The device check of the GPU's structured layout: both layouts on 128^2, 512^2 and
# 1024^2 flags in gusty wind (bench/scenes/gpu_flag.toml, no self-collision) with --backend
# gpu, one round each, about 1e8 particle-steps per run (at most 2000 steps); prints a small CSV
# to stdout:
#   size,layout,particle_steps_per_second,ns_per_particle_step,status,device
# and the structured/general speed-up per size on stderr. Under 2 minutes on a real GPU (the
# flags' building and loading take most of it at 1024^2). Runs from any directory.
#
# Without --gpu-device, the first EGL device that is not Mesa's software one (`maille info
# --backend gpu` lists them: an NVIDIA GPU) is used, else the default (llvmpipe where there is
# no GPU); the device column says which renderer ran.
#
# Usage: scripts/device_structured_check.sh PATH_TO_MAILLE [--gpu-device N]
set -euo pipefail
if [ $# -lt 1 ] || [ ! -x "$1" ]; then
  echo "usage: $0 PATH_TO_MAILLE [--gpu-device N]   (a built maille binary)" >&2
  exit 2
fi
maille=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
shift
here=$(cd "$(dirname "$0")" && pwd)
device=("$@")
if [ ${#device[@]} -eq 0 ]; then
  n=$("$maille" info --backend gpu 2>/dev/null |
    sed -n '/^devices/,$ s/^ *\([0-9][0-9]*\): \(.*\)$/\1 \2/p' | grep -v -i 'software' |
    head -1 | cut -d' ' -f1 || true)
  [ -n "$n" ] && device=(--gpu-device "$n")
fi
echo "device: ${device[*]:-default} $("$maille" info --backend gpu "${device[@]}" 2>/dev/null |
  sed -n 's/^renderer *//p')" >&2
csv=$("$here/bench_gpu_layouts.sh" --maille "$maille" --sizes 128,512,1024 --rounds 1 --out - \
  "${device[@]}")
echo "$csv" | awk -F, 'NR == 1 { print "size,layout,particle_steps_per_second,ns_per_particle_step,status,device"; next }
  { print $1 "," $3 "," $6 "," $7 "," $8 "," $9 }'
echo "$csv" | awk -F, 'NR > 1 && $8 == "ok" { pps[$1 "," $3] = $6; sizes[$1] = 1 }
  END { for (n in sizes) if ((n ",general") in pps && (n ",structured") in pps)
          printf "N=%s: structured / general = %.2f\n", n, pps[n ",structured"] / pps[n ",general"] > "/dev/stderr" }'
