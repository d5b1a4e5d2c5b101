#!/usr/bin/env bash
# Ctrl-C while a large scene builds or writes its first frame: exit 130, no .tmp left behind,
# stats.csv (with its header) complete.
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
grep -q "interrupted at step" "$out.log" || { echo "killed by the signal, not stopped"; exit 1; }
ls "$out"/*.tmp >/dev/null 2>&1 && { echo "temporary files left: $(ls "$out")"; exit 1; }
head -1 "$out/stats.csv" | grep -q "^time,step" || { echo "stats.csv lacks its header"; exit 1; }
echo "interrupted early, cleanly"
