#!/usr/bin/env bash
# Ctrl-C during `maille run`: it stops after the current step, exits 130, and every file it
# wrote is complete (stats.csv renamed into place, no .tmp left, frames parse).
set -u
maille=$1 scene=$2 out=$3
rm -rf "$out"
"$maille" run "$scene" --duration 1000 --every 50 --out "$out" >"$out.log" 2>&1 &
pid=$!
for _ in $(seq 100); do [ -e "$out/frame_000003.ply" ] && break; sleep 0.1; done
kill -INT $pid
wait $pid
rc=$?
[ $rc -eq 130 ] || { echo "exit code $rc, expected 130"; cat "$out.log"; exit 1; }
grep -q "interrupted at step" "$out.log" || { echo "no interruption message"; cat "$out.log"; exit 1; }
[ -s "$out/stats.csv" ] || { echo "stats.csv missing"; exit 1; }
ls "$out"/*.tmp >/dev/null 2>&1 && { echo "temporary files left"; exit 1; }
last=$(ls "$out"/frame_*.ply | tail -1)
grep -q "end_header" "$last" || { echo "last frame incomplete"; exit 1; }
echo "interrupted cleanly: $(wc -l <"$out/stats.csv") stats lines, $(ls "$out"/frame_*.ply | wc -l) frames"
