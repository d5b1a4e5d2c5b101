#!/usr/bin/env bash
# The default thread count against 1 and 2 threads on every example (the rule: threads
# never make a run slower), on the machine as it is ("idle": no load of ours) and with one core
# kept busy by a spinning shell loop.
#
# Each scene runs a fixed number of steps (after 10 untimed), set by a first run of 20 steps on
# one thread so that a run takes about 0.15 s (within [10, 10^6] steps): long enough that one
# time slice lost to another task is not the measurement, short enough that the sweep of every
# example takes a few minutes. Every
# setting runs in ROUNDS alternating rounds (scene by scene, the three settings in turn) and
# the fastest round is kept: a shared machine's noise is slow (a builder's burst lasts seconds),
# and alternating spreads it over the settings instead of landing on one.
#
# Prints CSV to stdout: scene,points,load,threads,default_threads,ns_per_particle_step,rounds
# (threads: default, 1 or 2; default_threads: the count the default ended on, in the fastest
# round), then a summary to stderr: per scene and load, the default over one thread (target:
# at most 1.5 with a core busy) and over the best of one and two (target: at most 1.1 idle).
# Usage: scripts/bench_threads.sh [MAILLE] [SCENE...]
#   (default: build/release/apps/maille/maille, every examples/*.toml; ROUNDS=3 in the
#   environment). OMP_WAIT_POLICY is left as the caller has it (unset: maille chooses).
set -euo pipefail
cd "$(dirname "$0")/.."
maille=${1:-build/release/apps/maille/maille}
shift || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(examples/*.toml)
rounds=${ROUNDS:-3}
busy=
stop_busy() { [ -n "$busy" ] && kill "$busy" 2>/dev/null; busy=; }
trap stop_busy EXIT
declare -A steps_of
for scene in "${scenes[@]}"; do
  steps_of[$scene]=$("$maille" bench "$scene" --steps 20 --warmup 1 --repeat 1 --backend cpu \
    --threads 1 --no-header | awk -F, '{ s = int(0.15 * 20 / ($6 > 0 ? $6 : 1e-9));
      print (s < 10 ? 10 : (s > 1000000 ? 1000000 : s)) }')
done
run() {  # scene load setting round: one row, or nothing when the scene cannot run
  local scene=$1 load=$2 setting=$3 round=$4 opt=
  [ "$setting" = default ] || opt="--threads $setting"
  "$maille" bench "$scene" --steps "${steps_of[$scene]}" --warmup 10 --repeat 1 --backend cpu $opt \
    --no-header 2>/dev/null |
    awk -F, -v s="$(basename "$scene" .toml)" -v l="$load" -v t="$setting" -v r="$round" \
      'NR==1 { printf "%s,%s,%s,%s,%s,%s\n", s, $2, l, t, $4, $7 }' || true
}
raw=$(mktemp)
trap 'stop_busy; rm -f "$raw"' EXIT
for load in idle busy; do
  if [ $load = busy ]; then
    bash -c 'while :; do :; done' &
    busy=$!
    sleep 0.5
  fi
  for round in $(seq 1 "$rounds"); do
    for scene in "${scenes[@]}"; do
      for setting in default 1 2; do run "$scene" $load $setting "$round" >>"$raw"; done
    done
  done
  stop_busy
done
echo "scene,points,load,threads,default_threads,ns_per_particle_step,rounds"
# The fastest round per (scene, load, setting), in the order first seen.
awk -F, -v rounds="$rounds" '
  { key = $1 "," $2 "," $3 "," $4
    if (!(key in best)) { order[++n] = key; best[key] = $6; threads[key] = $5 }
    else if ($6 + 0 < best[key] + 0) { best[key] = $6; threads[key] = $5 } }
  END { for (i = 1; i <= n; ++i) { k = order[i]; print k "," threads[k] "," best[k] "," rounds } }
' "$raw"
# The targets, per scene and load.
awk -F, '
  { v[$1 "," $3 "," $4] = $6; if (!($1 in seen)) { seen[$1] = 1; names[++n] = $1 } }
  END {
    printf "%-24s %-5s %9s %9s %9s %8s %8s\n", "scene", "load", "default", "1", "2", "d/1", "d/best" > "/dev/stderr"
    for (i = 1; i <= n; ++i) for (l = 0; l < 2; ++l) {
      load = l ? "busy" : "idle"; s = names[i]
      d = v[s "," load ",default"]; o = v[s "," load ",1"]; t = v[s "," load ",2"]
      if (d == "" || o == "" || t == "") continue
      b = o < t ? o : t
      printf "%-24s %-5s %9.1f %9.1f %9.1f %8.2f %8.2f\n", s, load, d, o, t, d / o, d / b > "/dev/stderr"
    }
  }
' <(awk -F, -v rounds="$rounds" '
  { key = $1 "," $2 "," $3 "," $4
    if (!(key in best) || $6 + 0 < best[key] + 0) best[key] = $6 }
  END { for (k in best) print k ",," best[k] }' "$raw")
