#!/usr/bin/env bash
# The viewer with sound on (docs/sound.md, "The viewer's Sound panel"), no sound card: under a
# virtual X server, with a JACK server on its dummy driver started under a name of its own (as
# tests/cli_play_jack.sh does), `maille-viewer SCENE --sound --sound-driver jack --frames N`
# opens its JACK client, plays, and exits 0 with its summary (frames played, xruns, CPU). With
# no server, sound is off with what was tried, and the viewer still runs and exits 0.
#   viewer_sound_jack.sh XVFB_RUN VIEWER EXAMPLES OUT
set -euo pipefail
xvfb=$1 viewer=$2 examples=$3 out=$4
rm -rf "$out"
mkdir -p "$out"
scene="$examples/sound_plucked_string.toml"
fail() { echo "FAIL: $*"; exit 1; }
# xvfb-run -a looks for a free display from 99 up; two started at once (the other viewer tests)
# may pick the same. This one starts its search elsewhere.
display=$((200 + $$ % 500))

# No server: the panel says what it tried, the viewer keeps running.
JACK_DEFAULT_SERVER="maille_none_$$" timeout 120 "$xvfb" -a -n "$display" "$viewer" "$scene" --sound \
  --sound-driver jack --frames 10 --width 320 --height 240 > "$out/none.stdout" 2> "$out/none.stderr" ||
  { cat "$out/none.stdout" "$out/none.stderr"; fail "the viewer failed without a JACK server"; }
cat "$out/none.stderr"
grep -q "sound is off: no audio output could be opened" "$out/none.stderr" &&
  grep -q "jack: no JACK server running" "$out/none.stderr" ||
  fail "without a server, the viewer does not say what it tried"
grep -q "sound off" "$out/none.stdout" || fail "no 'sound off' summary"

# A dummy server: 48 kHz, 256-frame periods, few ports, no real-time scheduling.
export JACK_DEFAULT_SERVER="maille_viewer_$$"
export JACK_NO_AUDIO_RESERVATION=1
jackd --no-realtime -n "$JACK_DEFAULT_SERVER" --port-max 32 --timeout 10000 -d dummy -r 48000 -p 256 \
  > "$out/jackd.log" 2>&1 &
jackd_pid=$!
cleanup() {
  kill "$jackd_pid" 2>/dev/null || true
  wait "$jackd_pid" 2>/dev/null || true
}
trap cleanup EXIT
for _ in $(seq 200); do
  if jack_lsp 2>/dev/null | grep -q "system:playback_1"; then break; fi
  sleep 0.05
done
jack_lsp 2>/dev/null | grep -q "system:playback_1" || { cat "$out/jackd.log"; fail "no server"; }

timeout 120 "$xvfb" -a -n "$display" "$viewer" "$scene" --sound --sound-driver jack --frames 90 --width 320 \
  --height 240 > "$out/viewer.stdout" 2> "$out/viewer.stderr" ||
  { cat "$out/viewer.stdout" "$out/viewer.stderr"; fail "the viewer with sound exited non-zero"; }
cat "$out/viewer.stdout"
line=$(grep "maille-viewer: sound on JACK" "$out/viewer.stdout") ||
  { cat "$out/viewer.stderr"; fail "no sound summary"; }
# Sound reached the device: frames were played and rendered (no count of xruns is asserted: a
# shared CI machine misses deadlines whatever the program does).
echo "$line" | grep -Eq "played [1-9][0-9]* frames, rendered [1-9][0-9]*, xruns [0-9]+" ||
  fail "nothing was played: $line"
echo "$line" | grep -q "client 'maille-viewer'" || fail "not the viewer's own JACK client: $line"
# The scene's [[control]] inputs open in the viewer too: the playable drum's MIDI port (JACK
# MIDI, the audio being on JACK) and its OSC server (on a port of this test's own).
port=$((20000 + $$ % 20000))
sed "s/^osc_port = .*/osc_port = $port/" "$examples/play_drum.toml" > "$out/drum.toml"
grep -q "osc_port = $port" "$out/drum.toml" || fail "no osc_port to replace in play_drum.toml"
timeout 120 "$xvfb" -a -n "$display" "$viewer" "$out/drum.toml" --sound --sound-driver jack --frames 30 \
  --width 320 --height 240 > "$out/drum.stdout" 2> "$out/drum.stderr" ||
  { cat "$out/drum.stdout" "$out/drum.stderr"; fail "the viewer with the drum exited non-zero"; }
cat "$out/drum.stdout"
grep -q "maille-viewer: controls: MIDI: virtual input port 'maille drum' (JACK MIDI)" "$out/drum.stdout" ||
  fail "no MIDI port"
grep -q "maille-viewer: controls: OSC: UDP 127.0.0.1:$port" "$out/drum.stdout" || fail "no OSC server"
# The JACK client left with the viewer.
sleep 0.2
if jack_lsp 2>/dev/null | grep -q "maille-viewer:"; then fail "the viewer's ports outlived it"; fi
echo "PASS: the viewer played through JACK and exited cleanly"
