#!/usr/bin/env bash
# OpenMP's wait policy follows the cores (apps/maille/main.cpp): with a core kept busy by another
# program and no policy set, maille starts again with OMP_WAIT_POLICY=passive (waiting threads
# sleep instead of spinning against a descheduled partner); a policy the user set is kept.
# Read from /proc/PID/environ while `maille validate` loads a large scene.
set -u
maille=$1 scene=$2
fail() { echo "FAIL: $*"; exit 1; }
bash -c 'while :; do :; done' &
busy=$!
trap 'kill $busy 2>/dev/null' EXIT
sleep 0.3
policy_of() {  # the OMP_WAIT_POLICY maille runs with, given the environment "$@"
  env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT "$@" "$maille" validate "$scene" >/dev/null 2>&1 &
  local pid=$!
  sleep 0.5
  tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | sed -n 's/^OMP_WAIT_POLICY=//p'
  kill -TERM $pid 2>/dev/null
  wait $pid 2>/dev/null
}
got=$(policy_of)
[ "$got" = passive ] || fail "a core busy, no policy set: OMP_WAIT_POLICY='$got', expected passive"
got=$(policy_of OMP_WAIT_POLICY=active)
[ "$got" = active ] || fail "the user's OMP_WAIT_POLICY=active became '$got'"
echo "passive when a core is busy; the user's policy kept"
