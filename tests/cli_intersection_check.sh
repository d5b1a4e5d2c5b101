#!/usr/bin/env bash
# The intersection gauge from the command line: two cloths placed through each other.
# - validate reports the crossing pairs of the initial state (a warning; the scene is valid);
# - run writes stats.csv's intersecting_pairs, warns once naming the first step, exits 0;
# - check = "every_step" stops the run at step 0 with exit 3, naming the stage.
set -u
maille=$1 scene=$2 out=$3
rm -rf "$out" "$out.every"
fail() { echo "FAIL: $*"; cat "$out.log" 2>/dev/null; exit 1; }
"$maille" validate "$scene" >"$out.log" 2>&1 || fail "validate failed"
grep -q "pairs of the surface's triangles cross in the initial state" "$out.log" ||
  fail "validate does not report the crossing"
"$maille" run "$scene" --steps 20 --out "$out" --no-frames >"$out.log" 2>&1 || fail "run failed"
grep -q "warning: .* of triangles of the self-colliding cloth cross at step 0" "$out.log" ||
  fail "no warning naming the first crossing"
[ "$(grep -c "cross at step" "$out.log")" = 1 ] || fail "the warning is not said once"
col=$(head -1 "$out/stats.csv" | tr ',' '\n' | grep -n "^intersecting_pairs$" | cut -d: -f1)
[ -n "$col" ] || fail "stats.csv has no intersecting_pairs column"
first=$(sed -n 2p "$out/stats.csv" | cut -d, -f"$col")
[ "$first" -gt 0 ] || fail "intersecting_pairs is $first in the first row"
"$maille" run "$scene" --steps 20 --out "$out.every" --no-frames \
  --set self_collision.check=every_step >"$out.log" 2>&1
rc=$?
[ $rc -eq 3 ] || fail "check = every_step: exit $rc, expected 3"
grep -q "stopped at step 0 .*by stage 'self_collision'" "$out.log" || fail "the stop names no step or stage"
echo "crossings: $first pairs in the first row; every_step stopped at step 0"
