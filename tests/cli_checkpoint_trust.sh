#!/usr/bin/env bash
# Checkpoints refuse what they cannot vouch for, each refusal exit 1 naming the file:
# - a file changed anywhere (a flipped byte in the frame counter, the scheme's history, the
#   positions; a truncated file): the checksum;
# - an edited scene (--set of the wind's density, drag, gusts, an obstacle's position, stiffness
#   or method, the self-collision radius, a drive's frequency or amplitude, --no-self-collision,
#   the implicit solver): the fingerprint;
# - another step: the message shows both steps with 17 digits.
# Scene: tests/data/checkpoint_everything.toml (drives, wind, self-collision, three obstacles).
set -u
maille=$1 scene=$2 out=$3
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
"$maille" run "$scene" --steps 40 --checkpoint-every 40 --no-frames --out "$out/base" >/dev/null \
  || fail "first run"
[ -s "$out/base/checkpoint.bin" ] || fail "no checkpoint written"

# refused LABEL PATTERN [run options...]: resuming a copy of the checkpoint exits 1, and the
# message holds PATTERN and the checkpoint's path; nothing is appended to its stats.csv.
refused() {
  local label=$1 pattern=$2
  shift 2
  "$maille" run "$scene" --steps 80 --no-frames --resume "$out/try" "$@" >"$out/try.log" 2>&1
  local rc=$?
  [ $rc -eq 1 ] || fail "$label: exit $rc, expected 1: $(cat "$out/try.log")"
  grep -q -- "$pattern" "$out/try.log" || fail "$label: no '$pattern' in: $(cat "$out/try.log")"
  case $pattern in *checkpoint.bin*) ;; *)
    grep -q "try/checkpoint.bin" "$out/try.log" || fail "$label: the file is not named";;
  esac
  cmp -s "$out/base/stats.csv" "$out/try/stats.csv" || fail "$label: stats.csv was changed"
  ls "$out/try"/frame_* >/dev/null 2>&1 && fail "$label: frames were written"
  return 0
}
fresh() { rm -rf "$out/try"; cp -r "$out/base" "$out/try"; }
# flip OFFSET: inverts one byte of the copy's checkpoint.
flip() {
  /usr/bin/python3 - "$out/try/checkpoint.bin" "$1" <<'PY'
import sys
path, at = sys.argv[1], int(sys.argv[2])
data = bytearray(open(path, 'rb').read())
at = at if at >= 0 else len(data) + at
data[at] ^= 0xff
open(path, 'wb').write(bytes(data))
PY
}

# The layout (checkpoint.hpp): magic 8, version 4, precision 4, fingerprint 8, scheme "leapfrog"
# (length 8 + 8), step 8, frames at 48, stats rows at 56, points at 64, time 72, step 80, the
# history's scheme at 88.
size=$(stat -c %s "$out/base/checkpoint.bin")
for at in 55 48 60 76 84 100 $((size / 2)) -9 -1; do
  fresh; flip "$at"
  refused "byte $at flipped" "corrupt"
done
fresh; truncate -s -1 "$out/try/checkpoint.bin"; refused "one byte short" "checkpoint"
fresh; truncate -s 12 "$out/try/checkpoint.bin"; refused "12 bytes" "truncated"
fresh; head -c 100 /dev/zero >"$out/try/checkpoint.bin"; refused "zeros" "not a Maille checkpoint"

for set in fields.wind.density=1.3 fields.wind.drag_coefficient=1.1 \
  fields.wind.gust_frequency=1.6 fields.wind.gust_wavelength=2.1 fields.wind.turbulence=0.5 \
  'obstacle[0].position=[0.3,0.81,0]' 'obstacle[0].stiffness=301' 'obstacle[0].damping=0.1' \
  'obstacle[2].threshold=0.021' 'obstacle[1].alpha=0.5' \
  self_collision.radius=0.029 self_collision.friction=0.1 \
  flag[0].drive.frequency=2.1 'flag[0].drive.amplitude=[0,0,0.11]' \
  'obstacle[1].method=conditional' 'fields.wind.density=1.2' 'fields.air_drag=0.21'; do
  fresh
  if [ "$set" = fields.wind.density=1.2 ]; then  # the file's own value: the same scene
    "$maille" run "$scene" --steps 80 --no-frames --resume "$out/try" --set "$set" >"$out/try.log" \
      2>&1 || fail "--set $set (no change) was refused: $(cat "$out/try.log")"
    continue
  fi
  refused "--set $set" "another model" --set "$set"
done
fresh; refused "--no-self-collision" "another model" --no-self-collision
fresh; refused "the implicit solver's settings" "another model" \
  --set simulation.implicit.tolerance=1e-7
# Another step: both values readable apart (1e-16 relative).
fresh; refused "another step" "h = 0.00015000000000000001 s" \
  --set simulation.step=0.00015000000000000001
grep -q "h = 0.00014999999999999999 s" "$out/try.log" || fail "the checkpoint's step is not shown: $(cat "$out/try.log")"

# What does not change the trajectory is accepted: the duration, the output cadence, threads.
fresh
"$maille" run "$scene" --steps 80 --no-frames --resume "$out/try" --threads 2 \
  --set simulation.output_every=7 --set scene.description=other --set simulation.duration=9 \
  >"$out/try.log" 2>&1 || fail "output-only changes were refused: $(cat "$out/try.log")"
echo "checkpoints: corrupt, truncated, edited and re-stepped files refused; output changes accepted"
