#!/usr/bin/env bash
# Ctrl-C during an implicit step that would last minutes (accepted keys: 100,000 VBD sweeps at
# h = 0.1 s): the solver stops between two sweeps and the run exits 130 at once, at the last
# whole step (0), its files complete (Python's test checks the state to the bit). Then the warning for an
# unconverged implicit run: matrix_free at h = 0.1 s ends with exit 0, but says so.
set -u
maille=$1 scene=$2 out=$3
rm -rf "$out" "$out.u"
fail() { echo "FAIL: $*"; cat "$out.log" 2>/dev/null; exit 1; }
"$maille" run "$scene" --steps 3 --out "$out" --no-frames \
  --set simulation.integrator=implicit_euler --set simulation.step=0.1 \
  --set simulation.implicit.solver=vbd --set simulation.implicit.iterations=100000 \
  >"$out.log" 2>&1 &
pid=$!
# The output directory is made once the simulator is built: then inside the first step (about a
# minute long on this machine).
for _ in $(seq 300); do [ -d "$out" ] && break; sleep 0.1; done
sleep 1
kill -INT $pid
for _ in $(seq 300); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
if kill -0 $pid 2>/dev/null; then kill -KILL $pid; fail "still running 30 s after Ctrl-C"; fi
wait $pid
rc=$?
[ $rc -eq 130 ] || fail "exit $rc, expected 130"
grep -q "interrupted at step 0" "$out.log" || fail "not stopped at the last whole step (0)"
[ -s "$out/stats.csv" ] || fail "no stats.csv"
ls "$out"/*.tmp >/dev/null 2>&1 && fail "temporary files left"

"$maille" run "$scene" --steps 8 --out "$out.u" --no-frames --set simulation.integrator=implicit_euler \
  --set simulation.implicit.solver=matrix_free --set simulation.step=0.1 >"$out.log" 2>&1 ||
  fail "the unconverged run failed"
grep -q "warning: implicit_euler (matrix_free) ended .* unconverged, the first at step" "$out.log" ||
  fail "no warning for the unconverged steps"
echo "stopped inside the step; unconverged steps said"
