#!/usr/bin/env bash
# `maille play` through JACK with no sound card (docs/sound.md "Playing live", "Tests"): a JACK
# server with its dummy driver under a name of its own, and a recording client of its own
# (tests/tools/jack_record.cpp) that records the player's ports in freewheel mode.
#   cli_play_jack.sh CASE MAILLE JACK_RECORD WAV_MATCH WAV_PEAKS EXAMPLES OUT
# CASE:
#   equal     the recording equals `maille run --audio` (float32) of the same scene, bit for bit
#   midi      a note (JACK MIDI) strikes the silent drum within two periods; a CC retunes it:
#             the fundamental moves by sqrt(k1 / k0) (every mode of the lattice scales so)
#   osc       an OSC message strikes the drum (what the player sent, --record, in real time: no
#             recording client); an out-of-range value is clamped and said once
#   no_server without a server (and no other device): exit 1, naming what was tried, no hang
set -euo pipefail
# The freewheel cases run twice at most: a JACK graph in freewheel stalled on the loaded
# development machine (2 runs in 5 of a case since moved off freewheel, none seen on these),
# and the recorder then fails after 20 s without progress. A second run clears a stall; a
# wrong result fails both.
if [ -z "${MAILLE_PLAY_RETRY:-}" ] && { [ "$1" = equal ] || [ "$1" = midi ]; }; then
  MAILLE_PLAY_RETRY=1 bash "$0" "$@" && exit 0
  echo "cli_play_jack.sh: $1 failed once; running it again (a freewheel stall fails one run)"
  MAILLE_PLAY_RETRY=1 exec bash "$0" "$@"
fi
case_name=$1 maille=$2 rec=$3 match=$4 peaks=$5 examples=$6 out=$7
rm -rf "$out"
mkdir -p "$out"

if [ "$case_name" = no_server ]; then
  export JACK_DEFAULT_SERVER="maille_none_$$"
  set +e
  timeout 60 "$maille" play "$examples/play_drum.toml" --driver jack --duration 1 \
    > "$out/stdout" 2> "$out/stderr"
  rc=$?
  set -e
  cat "$out/stderr"
  [ $rc -eq 1 ] || { echo "FAIL: exit $rc, expected 1"; exit 1; }
  grep -q "tried:" "$out/stderr" && grep -q "jack: no JACK server running" "$out/stderr" ||
    { echo "FAIL: the message does not name what was tried"; exit 1; }
  echo "PASS: no server: exit 1, named"
  exit 0
fi

# The server: dummy driver, 48 kHz, 256-frame periods, few ports (CI's shared memory is small),
# no real-time scheduling (no privileges needed). Stopped by its process id.
export JACK_DEFAULT_SERVER="maille_test_$$_$case_name"
export JACK_NO_AUDIO_RESERVATION=1
jackd --no-realtime -n "$JACK_DEFAULT_SERVER" --port-max 32 --timeout 10000 -d dummy -r 48000 -p 256 \
  > "$out/jackd.log" 2>&1 &
jackd_pid=$!
player_pid=""
cleanup() {
  [ -n "$player_pid" ] && kill "$player_pid" 2>/dev/null || true
  kill "$jackd_pid" 2>/dev/null || true
  wait "$jackd_pid" 2>/dev/null || true
}
trap cleanup EXIT
for _ in $(seq 200); do
  if jack_lsp 2>/dev/null | grep -q "system:playback_1"; then break; fi
  sleep 0.05
done
jack_lsp 2>/dev/null | grep -q "system:playback_1" || { cat "$out/jackd.log"; echo "FAIL: no server"; exit 1; }

case "$case_name" in
  equal)
    # The plucked string at one step per sample of 48 kHz, a fixed gain, float32: what run
    # writes and what play sends are the same floats.
    sets=(--set simulation.step=2.0833333333333333e-05 --set audio.rate=48000
          --set audio.gain=0.1 --set audio.format=float32)
    scene="$examples/sound_plucked_string.toml"
    # The reference is longer than anything the player can send before it is stopped, so that
    # every recorded frame has its counterpart (the recording starts when freewheel does).
    "$maille" run "$scene" "${sets[@]}" --duration 6 --no-frames --audio "$out/run.wav" \
      --out "$out/run" > /dev/null
    "$maille" play "$scene" "${sets[@]}" --driver jack --duration 6 --record "$out/sent.wav" \
      > "$out/play.stdout" 2> "$out/play.stderr" &
    player_pid=$!
    "$rec" --from maille --channels 2 --frames 96000 --out "$out/recorded.wav"
    kill -INT "$player_pid"
    wait "$player_pid"
    player_pid=""
    cat "$out/play.stdout"
    grep -q "xruns" "$out/play.stdout" || { echo "FAIL: no summary"; exit 1; }
    "$match" "$out/run.wav" "$out/recorded.wav" 96000
    "$match" "$out/run.wav" "$out/sent.wav" 96000   # --record: every sample sent
    ;;
  midi)
    # A small drum (rings = 8) at rest; note 60 velocity 100 at recorded frame 4800 (0.1 s),
    # CC 74 = 100 at frame 48000 (1 s). JACK MIDI through RtMidi's JACK API.
    scene="$examples/play_drum.toml"
    "$maille" play "$scene" --set membrane[0].rings=8 --set listen[0].point=skin:70 --set control[0].excite.point=skin:40 --set audio.osc_port=$((20000 + $$ % 20000)) --driver jack \
      --duration 30 > "$out/play.stdout" 2> "$out/play.stderr" &
    player_pid=$!
    "$rec" --from maille --channels 1 --frames 120000 --out "$out/recorded.wav" \
      --midi-to "maille-midi:maille drum" --note 4800:60:100 --cc 48000:74:100 | tee "$out/rec.txt"
    kill -INT "$player_pid" 2>/dev/null || true
    wait "$player_pid" || true
    player_pid=""
    cat "$out/play.stdout" "$out/play.stderr"
    # Silent before the note; sound within two periods (512 frames) of it.
    python3 - "$out/recorded.wav" <<'EOF'
import struct, sys
data = open(sys.argv[1], "rb").read()
i = data.index(b"data") + 8
x = struct.unpack("<%df" % ((len(data) - i) // 4), data[i:])
onset = next(k for k, v in enumerate(x) if abs(v) > 1e-6)
before = max(abs(v) for v in x[:4800])
print("silent before the note: peak %.3g; onset at frame %d, %d frames after the note" % (before, onset, onset - 4800))
assert before == 0.0, "sound before the note"
assert 0 <= onset - 4800 <= 512, "the strike did not start within two periods"
EOF
    # k: 16550 -> 8000 + (33100 - 8000) * 100 / 127 = 27763.8 N/m: f1 / f0 = sqrt(27763.8 / 16550).
    # The fundamental of this small drum: 243.6 Hz before, 315.5 Hz after (measured).
    f0=$("$peaks" "$out/recorded.wav" --from 0.2 --to 0.95 --min 180 --max 290 --count 1 | awk '$2 == "Hz" {print $1; exit}')
    f1=$("$peaks" "$out/recorded.wav" --from 1.2 --to 2.4 --min 260 --max 370 --count 1 | awk '$2 == "Hz" {print $1; exit}')
    python3 -c "
import math, sys
f0, f1 = $f0, $f1
want = math.sqrt((8000 + 25100 * 100 / 127) / 16550)
print('fundamental %.3f Hz -> %.3f Hz: ratio %.5f, sqrt(k1/k0) = %.5f, off by %.3f %%' % (f0, f1, f1 / f0, want, 100 * abs(f1 / f0 / want - 1)))
sys.exit(0 if abs(f1 / f0 / want - 1) < 0.005 else 1)"
    ;;
  osc)
    port=$((20000 + $$ % 20000))
    scene="$examples/play_drum.toml"
    "$maille" play "$scene" --set membrane[0].rings=8 --set listen[0].point=skin:70 --set control[0].excite.point=skin:40 --set audio.osc_port=$port --driver jack \
      --duration 30 --record "$out/sent.wav" > "$out/play.stdout" 2> "$out/play.stderr" &
    player_pid=$!
    for _ in $(seq 200); do jack_lsp 2>/dev/null | grep -q "maille:out_1" && break; sleep 0.05; done
    send() {  # address, float: one OSC message over UDP to 127.0.0.1
      python3 -c "
import socket, struct, sys
def pad(b): return b + b'\0' * (4 - len(b) % 4)
msg = pad(sys.argv[1].encode()) + pad(b',f') + struct.pack('>f', float(sys.argv[2]))
socket.socket(socket.AF_INET, socket.SOCK_DGRAM).sendto(msg, ('127.0.0.1', int(sys.argv[3])))" "$1" "$2" "$port"
    }
    send /maille/drum/tension 7.0     # out of [0, 1]: clamped to 1, said once
    send /maille/drum/tension 9.0
    send /maille/drum/strike 0.9
    sleep 0.5
    # No recording client here: what the player sent (--record) is what is checked.
    kill -INT "$player_pid"
    wait "$player_pid" || true
    player_pid=""
    cat "$out/play.stdout" "$out/play.stderr"
    [ "$(grep -c "clamped" "$out/play.stderr")" = 1 ] || { echo "FAIL: the clamp is not said once"; exit 1; }
    python3 - "$out/sent.wav" <<'EOF'
import struct, sys
data = open(sys.argv[1], "rb").read()
i = data.index(b"data") + 8
x = struct.unpack("<%df" % ((len(data) - i) // 4), data[i:])
peak = max(abs(v) for v in x)
print("after the OSC strike: peak %.3g, all finite" % peak)
assert all(v == v and abs(v) < 1e30 for v in x)
assert peak > 1e-3, "the OSC strike made no sound"
EOF
    ;;
esac
echo "PASS: $case_name"
