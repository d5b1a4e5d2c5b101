#!/usr/bin/env bash
# The viewer's render loop holds a core, so its physics threads wait passively
# (maille::wait_passively_when_cores_are_shared, cores.hpp): with no policy set, maille-viewer
# starts again with OMP_WAIT_POLICY=passive; a policy the user set is kept. Read from
# /proc/PID/environ while the viewer runs under Xvfb (execv keeps the PID).
#   viewer_wait_policy.sh XVFB_RUN VIEWER SCENE
set -u
xvfb=$1 viewer=$2 scene=$3
fail() { echo "FAIL: $*"; exit 1; }
policy_of() {  # the OMP_WAIT_POLICY the viewer runs with, given the environment "$@"
  env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT "$@" "$xvfb" -a "$viewer" "$scene" --frames 100000 \
    >/dev/null 2>&1 &
  local runner=$! pid=
  for _ in $(seq 1 100); do
    pid=$(pgrep -n -f "^$viewer $scene") && break
    sleep 0.1
  done
  sleep 1.5
  [ -n "$pid" ] && tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | sed -n 's/^OMP_WAIT_POLICY=//p'
  [ -n "$pid" ] && kill -TERM "$pid" 2>/dev/null
  wait $runner 2>/dev/null
}
got=$(policy_of)
[ "$got" = passive ] || fail "no policy set: the viewer runs with OMP_WAIT_POLICY='$got', expected passive"
got=$(policy_of OMP_WAIT_POLICY=active)
[ "$got" = active ] || fail "the user's OMP_WAIT_POLICY=active became '$got'"
echo "the viewer waits passively; the user's policy kept"
