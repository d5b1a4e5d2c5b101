#!/usr/bin/env bash
# Ctrl-C while a large scene builds or writes its first frame: exit 130 and no .tmp left behind;
# either the scene was still loading (nothing written: "interrupted while loading the scene") or
# the run had started (stats.csv complete, with its header: "interrupted at step").
set -u
maille=$1 scene=$2 out=$3
rm -rf "$out"
"$maille" run "$scene" --out "$out" >"$out.log" 2>&1 &
pid=$!
sleep 0.5
kill -INT $pid
wait $pid
rc=$?
cat "$out.log"
[ $rc -eq 130 ] || { echo "exit code $rc, expected 130"; exit 1; }
# 130 is also what the shell reports for a process killed by SIGINT: the message tells them apart.
if grep -q "interrupted while loading the scene" "$out.log"; then
  [ -e "$out" ] && { echo "interrupted while loading, yet $out was made"; exit 1; }
  echo "interrupted while loading, cleanly"
  exit 0
fi
grep -q "interrupted at step" "$out.log" || { echo "killed by the signal, not stopped"; exit 1; }
ls "$out"/*.tmp >/dev/null 2>&1 && { echo "temporary files left: $(ls "$out")"; exit 1; }
head -1 "$out/stats.csv" | grep -q "^time,step" || { echo "stats.csv lacks its header"; exit 1; }
echo "interrupted early, cleanly"
