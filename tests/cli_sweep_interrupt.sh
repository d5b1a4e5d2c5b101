#!/usr/bin/env bash
# cli_sweep_interrupt.sh MAILLE SWEEP OUT: Ctrl-C during a one-process sweep stops after the
# current case with exit 130, a complete summary of the cases done (one row per done marker)
# and no temporary file; the same command then runs the other cases only, and the summary
# equals that of a sweep never interrupted (every column but wall_seconds, rank and ns_*).
set -u
maille=$1 sweep=$2 out=$3
here=$(dirname "$0")
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

"$maille" sweep "$sweep" --out "$out/whole" --threads 1 >"$out/whole.log" 2>&1 \
  || { cat "$out/whole.log"; fail "uninterrupted sweep"; }
total=$(ls "$out"/whole/cases/*/done | wc -l)

"$maille" sweep "$sweep" --out "$out/split" --threads 1 >"$out/split.log" 2>&1 &
pid=$!
for _ in $(seq 400); do
  [ "$(ls "$out"/split/cases/*/done 2>/dev/null | wc -l)" -ge 2 ] && break
  sleep 0.025
done
kill -INT $pid
wait $pid
rc=$?
cat "$out/split.log"
[ $rc -eq 130 ] || fail "exit code $rc after Ctrl-C, expected 130"
done_before=$(ls "$out"/split/cases/*/done | wc -l)
rows=$(($(wc -l <"$out/split/summary.csv") - 1))
[ "$rows" -eq "$done_before" ] || fail "$rows summary rows for $done_before cases done"
[ "$done_before" -lt "$total" ] || fail "every case was done before Ctrl-C: nothing to resume"
[ -z "$(find "$out/split" -name '*.tmp')" ] || fail "temporary files left"
grep -q "interrupted: $((total - done_before)) cases not run" "$out/split.log" \
  || fail "no interruption message"

"$maille" sweep "$sweep" --out "$out/split" --threads 1 >"$out/resume.log" 2>&1 \
  || { cat "$out/resume.log"; fail "resume"; }
cat "$out/resume.log"
grep -q "$done_before of $total cases already done" "$out/resume.log" || fail "resume ran done cases"
/usr/bin/python3 "$here/sweep_compare.py" "$out/whole/summary.csv" "$out/split/summary.csv" \
  || fail "the resumed summary differs"
echo "Ctrl-C after $done_before of $total cases; resumed to the same summary"
