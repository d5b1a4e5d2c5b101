#!/usr/bin/env bash
# Ctrl-C during `maille run --audio`: the run stops after the current step, exits 130, and the
# WAV holds every sample simulated so far, complete (a valid file, no .tmp left).
set -u
maille=$1 peaks=$2 scene=$3 out=$4
rm -rf "$out"
mkdir -p "$out"
"$maille" run "$scene" --duration 1000 --no-frames --out "$out/run" --audio "$out/long.wav" \
  >"$out/log" 2>&1 &
pid=$!
sleep 1
kill -INT $pid
wait $pid
rc=$?
cat "$out/log"
[ $rc -eq 130 ] || { echo "FAIL: exit code $rc, expected 130"; exit 1; }
grep -q "and the audio of the simulated time are complete" "$out/log" || { echo "FAIL: message"; exit 1; }
ls "$out"/*.tmp >/dev/null 2>&1 && { echo "FAIL: temporary file left"; exit 1; }
"$peaks" "$out/long.wav" --channel 1 --count 1 || { echo "FAIL: the WAV does not read"; exit 1; }
samples=$(grep -o "16-bit PCM, [0-9]* samples" "$out/log" | grep -o "[0-9]* samples" | grep -o "[0-9]*")
[ "${samples:-0}" -gt 1000 ] || { echo "FAIL: too few samples ($samples)"; exit 1; }
echo "interrupted cleanly with $samples samples"
