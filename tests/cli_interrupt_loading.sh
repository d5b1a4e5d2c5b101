#!/usr/bin/env bash
# SIGINT and SIGTERM during scene loading stop `maille validate`, `info` and `run` at once with
# exit 130 and a message (loading used to ignore them, and a hanging set-up could only
# be killed with SIGKILL). The scene (a 60^3 lattice, 2.8 million links) takes seconds to build.
set -u
maille=$1 scene=$2 out=$3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$out" "$out.log"
for cmd in validate info run; do
  for sig in INT TERM; do
    args=("$cmd" "$scene")
    [ $cmd = run ] && args+=(--out "$out")
    "$maille" "${args[@]}" >"$out.log" 2>&1 &
    pid=$!
    sleep 0.3
    t0=$(date +%s.%N)
    kill -$sig $pid
    wait $pid
    rc=$?
    took=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
    [ $rc -eq 130 ] || fail "$cmd, SIG$sig: exit $rc, expected 130: $(cat "$out.log")"
    grep -q "interrupted while loading the scene" "$out.log" ||
      fail "$cmd, SIG$sig: no message: $(cat "$out.log")"
    awk -v t="$took" 'BEGIN { exit !(t < 1.0) }' || fail "$cmd, SIG$sig: took $took s to stop"
    [ -e "$out" ] && fail "$cmd, SIG$sig: $out was made"
  done
done
echo "validate, info and run stop during loading (exit 130, nothing written)"
