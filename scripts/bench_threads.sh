#!/usr/bin/env bash
# The default thread count against 1 and 2 threads (issue 24: "threads that never make a run
# slower"), on an idle machine and with one core busy (a shell loop spinning beside it).
# Prints CSV: scene,load,threads,default_threads,ns_per_particle_step (the fastest of --repeat).
# Usage: scripts/bench_threads.sh [MAILLE] [SCENE...]   (default: build/release, flag_64 and
# flag_in_wind). OMP_WAIT_POLICY is left as the caller has it (unset: libgomp spins).
set -euo pipefail
cd "$(dirname "$0")/.."
maille=${1:-build/release/apps/maille/maille}
shift || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(examples/flag_64.toml examples/flag_in_wind.toml)
busy=
stop_busy() { [ -n "$busy" ] && kill "$busy" 2>/dev/null; busy=; }
trap stop_busy EXIT
row() {  # scene load threads-option
  local scene=$1 load=$2 opt=$3
  "$maille" bench "$scene" --steps 400 --warmup 100 --repeat 3 $opt --no-header |
    awk -F, -v s="$(basename "$scene" .toml)" -v l="$load" -v o="${opt:-default}" \
      'NR==1 { printf "%s,%s,%s,%s,%s\n", s, l, o, $4, $7 }'
}
echo "scene,load,threads,default_threads,ns_per_particle_step"
for load in idle busy; do
  if [ $load = busy ]; then
    bash -c 'while :; do :; done' &
    busy=$!
    sleep 0.5
  fi
  for scene in "${scenes[@]}"; do
    row "$scene" $load ""
    row "$scene" $load "--threads 1"
    row "$scene" $load "--threads 2"
  done
  stop_busy
done
