# shellcheck shell=bash disable=SC2034,SC2154  # sets and reads the caller's variables
# Shared by scripts/bench_gpu.sh and scripts/bench_gpu_layouts.sh (sourced, from the repository
# root, under set -euo pipefail): their common options, the build of the CLI they time, and the
# name of the GPU that makes their figures.

# Parses the options into sizes, steps, out, device (an array: `--gpu-device N`, or empty) and
# maille; --rounds into rounds only for a caller that set a default for it. Anything else: the
# caller's $usage on stderr, exit 2. The caller sets its defaults first.
gpu_bench_options() {
  device=()
  maille=
  while [ $# -gt 0 ]; do
    case "$1" in
      --sizes) sizes=$2; shift 2 ;;
      --steps) steps=$2; shift 2 ;;
      --out) out=$2; shift 2 ;;
      --rounds) [ -n "${rounds+set}" ] || gpu_bench_usage; rounds=$2; shift 2 ;;
      --gpu-device) device=(--gpu-device "$2"); shift 2 ;;
      --maille) maille=$2; shift 2 ;;
      *) gpu_bench_usage ;;
    esac
  done
}

gpu_bench_usage() {
  echo "$usage" >&2
  exit 2
}

# Without --maille: the release build of the CLI.
gpu_bench_build_maille() {
  if [ -z "$maille" ]; then
    scripts/setup.sh
    cmake --preset release >/dev/null
    cmake --build --preset release --target maille
    maille=build/release/apps/maille/maille
  fi
}

# The GPU driver's renderer string, commas dropped (a CSV field), or "unavailable".
gpu_bench_gpu_name() {
  local name
  name=$("$maille" info --backend gpu "${device[@]}" 2>/dev/null | sed -n 's/^renderer *//p' |
    tr -d ',' || true)
  echo "${name:-unavailable}"
}
