#!/usr/bin/env bash
# Outputs never destroy what the user did not name as an output (never a lost file):
# --audio into a FIFO (a player's pipe) or a device writes into it, leaving the node; --audio
# naming the scene, stats.csv or a frame is refused before anything is written; an empty path
# is a usage error; a recording beyond the memory budget is refused up front; a bad
# --checkpoint-every says its range in a few digits.
set -u
maille=$1 examples=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
scene="$work/string.toml"
cp "$examples/sound_plucked_string.toml" "$scene"
fail() { echo "FAIL: $*"; exit 1; }

# 1. A FIFO read by a "player": the WAV goes through it, the FIFO stays a FIFO.
mkfifo "$work/pipe.wav"
cat "$work/pipe.wav" >"$work/received.wav" &
reader=$!
"$maille" run "$scene" --duration 0.05 --no-frames --out "$work/o1" --audio "$work/pipe.wav" \
  >"$work/o1.log" 2>&1 || { cat "$work/o1.log"; fail "run into a FIFO"; }
wait $reader
[ -p "$work/pipe.wav" ] || fail "the FIFO was replaced"
[ "$(head -c 4 "$work/received.wav")" = "RIFF" ] || fail "the player got no WAV"
[ -e "$work/pipe.wav.tmp" ] && fail "a temporary was left"

# A character device: /dev/null stays the device (as root, a rename would replace it).
before=$(stat -c '%F %t:%T' /dev/null)
"$maille" run "$scene" --duration 0.05 --no-frames --out "$work/o2" --audio /dev/null \
  >"$work/o2.log" 2>&1 || { cat "$work/o2.log"; fail "run into /dev/null"; }
[ "$(stat -c '%F %t:%T' /dev/null)" = "$before" ] || fail "/dev/null was replaced"

# A symbolic link: the file it names is written, the link kept.
echo old >"$work/target.wav"
ln -s "$work/target.wav" "$work/link.wav"
"$maille" run "$scene" --duration 0.05 --no-frames --out "$work/o3" --audio "$work/link.wav" \
  >"$work/o3.log" 2>&1 || { cat "$work/o3.log"; fail "run into a link"; }
[ -L "$work/link.wav" ] || fail "the link was replaced"
[ "$(head -c 4 "$work/target.wav")" = "RIFF" ] || fail "the link's target was not written"

# 9. --audio naming an input or another output of the same run: refused, nothing touched.
cp "$scene" "$work/scene.copy"
for target in "$scene" "$work/o4/stats.csv" "$work/o4/frame_000000.ply" "$work/o4"; do
  "$maille" run "$scene" --duration 0.05 --out "$work/o4" --audio "$target" >"$work/o4.log" 2>&1
  rc=$?
  [ $rc -eq 2 ] || { cat "$work/o4.log"; fail "--audio $target: exit $rc, expected 2"; }
  grep -q "name another file" "$work/o4.log" || { cat "$work/o4.log"; fail "no reason given"; }
done
cmp -s "$scene" "$work/scene.copy" || fail "the scene file changed"
[ -e "$work/o4" ] && fail "an output directory was made for a refused run"

# 14. Empty output paths are usage errors.
"$maille" run "$scene" --duration 0.05 --no-frames --out "$work/o5" --audio "" >"$work/o5.log" 2>&1
[ $? -eq 2 ] || fail "--audio \"\" was accepted"
cat >"$work/sweep.toml" <<TOML
scene = "string.toml"
duration = 0.01
[axes]
"fields.air_drag" = [0.0]
TOML
(cd "$work" && "$maille" sweep sweep.toml --out "" >sweep.log 2>&1)
[ $? -eq 2 ] || fail "sweep --out \"\" was accepted"
[ -e "$work/cases" ] && fail "the sweep wrote into the current folder"

# 11. A recording beyond the memory budget is refused before the run.
MAILLE_MEMORY_BUDGET=100000 "$maille" run "$scene" --duration 10 --no-frames --out "$work/o6" \
  --audio "$work/big.wav" >"$work/o6.log" 2>&1
rc=$?
[ $rc -eq 2 ] || { cat "$work/o6.log"; fail "a recording beyond the budget: exit $rc"; }
grep -q "held in memory" "$work/o6.log" || { cat "$work/o6.log"; fail "no budget message"; }

# 14. --checkpoint-every 0: a short message.
"$maille" run "$scene" --steps 10 --checkpoint-every 0 --out "$work/o7" >"$work/o7.log" 2>&1
[ $? -eq 2 ] || fail "--checkpoint-every 0 accepted"
[ "$(wc -c <"$work/o7.log")" -lt 400 ] || { cat "$work/o7.log"; fail "long message"; }

echo "outputs guarded"
