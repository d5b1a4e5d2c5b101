#!/usr/bin/env bash
# Ctrl-C during an MP4 render: SIGINT goes to the whole foreground process group (maille and,
# before the fix, ffmpeg). maille must stop, let ffmpeg finish the video with the frames made so
# far, and exit 130; no .tmp left.
set -u
maille=$1 scene=$2 out=$3
rm -f "$out" "$out.tmp"
setsid "$maille" render "$scene" --out "$out" --duration 1000 --width 160 --height 120 \
  --samples 1 >"$out.log" 2>&1 &
pid=$!
sleep 2
kill -INT -- -$pid  # the process group, as a terminal's Ctrl-C does
wait $pid
rc=$?
cat "$out.log"
[ $rc -eq 130 ] || { echo "exit code $rc, expected 130"; exit 1; }
[ -s "$out" ] || { echo "no video"; exit 1; }
[ -e "$out.tmp" ] && { echo "temporary left"; exit 1; }
if command -v ffprobe >/dev/null; then
  frames=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames \
    -of csv=p=0 "$out")
  [ "${frames:-0}" -gt 0 ] || { echo "the video has no frame"; exit 1; }
  echo "video of $frames frames"
fi
echo "interrupted render kept its video"
