#!/usr/bin/env bash
# `maille run --audio`: the plucked string example writes a complete WAV (no .tmp left), the
# summary states the gain, `info` lists the listeners, and the fundamental measured from the
# written file (wav_peaks: FFT, peak refined between bins) is the discrete string's mode.
set -u
maille=$1 peaks=$2 examples=$3 out=$4
rm -rf "$out"
mkdir -p "$out"
scene=$examples/sound_plucked_string.toml
"$maille" run "$scene" --audio "$out/wav/string.wav" --no-frames --out "$out/run" >"$out/log" 2>&1
rc=$?
cat "$out/log"
[ $rc -eq 0 ] || { echo "FAIL: exit code $rc"; exit 1; }
[ -s "$out/wav/string.wav" ] || { echo "FAIL: no WAV"; exit 1; }
ls "$out"/wav/*.tmp >/dev/null 2>&1 && { echo "FAIL: temporary file left"; exit 1; }
grep -q "maille: audio .*string.wav: 44100 Hz 16-bit PCM, 66151 samples .*gain .*exact: every 1 step" "$out/log" ||
  { echo "FAIL: no audio summary"; exit 1; }
"$maille" info "$scene" | grep -q "listen       channel 1: force of string:0 (point 1)" ||
  { echo "FAIL: info does not list the listeners"; exit 1; }
# The discrete string's fundamental with leapfrog's dispersion: 219.8855 Hz (test_sound.cpp).
"$peaks" "$out/wav/string.wav" --channel 1 --from 0.05 --min 50 --max 400 --expect 219.8855 \
  --tolerance 0.005 || { echo "FAIL: fundamental"; exit 1; }
# --set reaches the sound keys: float samples at another rate, resampled (the step is 1/44100).
"$maille" run "$scene" --duration 0.2 --set audio.format=float32 --set audio.rate=48000 \
  --audio "$out/float.wav" --no-frames --out "$out/run2" >"$out/log2" 2>&1 || { cat "$out/log2"; exit 1; }
grep -q "48000 Hz 32-bit float, 9601 samples.*resampled (band-limited windowed sinc)" "$out/log2" ||
  { cat "$out/log2"; echo "FAIL: --set audio.*"; exit 1; }
echo "ok"
