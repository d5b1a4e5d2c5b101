#!/usr/bin/env bash
# Installs the Debian 12 packages Maille needs to build and test.
# Idempotent and quiet: does nothing when every package is already present.
# Usage: scripts/setup.sh [web] [EXTRA_PACKAGE...]   (other scripts add theirs, e.g. fuzz.sh: clang)
#   web  the browser build (scripts/web.sh): emscripten, Chromium for the headless page test and
#        Node.js with npm (the test's driver, playwright-core, comes from web/package-lock.json).
set -euo pipefail

extra=()
for a in "$@"; do
  if [ "$a" = web ]; then
    extra+=(emscripten chromium nodejs)
    # npm is its own Debian package; a Node.js from elsewhere (NodeSource) already carries it.
    command -v npm >/dev/null || extra+=(npm)
  else
    extra+=("$a")
  fi
done

packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev libtomlplusplus-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev libomp-dev
  # Rendering (src/render, apps/viewer, `maille render`): OpenGL 4.5 core through libepoxy, EGL
  # surfaceless on Mesa's software driver for headless frames, GLFW + Dear ImGui for the viewer,
  # stb_image_write for PNG, ffmpeg for MP4, Xvfb for the viewer test with no display.
  libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev libimgui-dev
  libstb-dev ffmpeg xvfb xauth
  # The report pipeline (cli.report_quick: figures with Debian's matplotlib) and the peer engine
  # of its comparison (bench/peer_bullet: Bullet's soft-body cloth; built only when present).
  python3-matplotlib libbullet-dev
  # The Python module (python/: pybind11 over NumPy views, tested with pytest) and sweeps across
  # machines (`maille sweep` under mpirun: Open MPI, built in when present).
  pybind11-dev python3-dev python3-numpy python3-pytest libopenmpi-dev openmpi-bin
  # `pip install .` of the module into a virtual environment (docs/python.md, "Installing").
  python3-venv
  # Live sound (`maille play`, docs/sound.md): RtAudio (JACK, ALSA, PulseAudio), JACK directly
  # (libjack-jackd2-dev), RtMidi and liblo for the controls; built in when present. jackd2 is the
  # server the tests start with its dummy driver (no sound card); without recommends (it would
  # pull a Qt desktop), its real-time question preseeded below so the install never prompts.
  jackd2 libjack-jackd2-dev librtaudio-dev librtmidi-dev liblo-dev
  # Benchmarks only (bench_step, docs/implicit.md): CHOLMOD against the coarse correction's
  # LDL^T, Highway's dynamic dispatch against the VBD lanes' table; the engine uses neither.
  libsuitesparse-dev libhwy-dev
  "${extra[@]}"
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
# jackd2 asks whether to enable real-time scheduling for the audio group: answered no up front.
echo "jackd2 jackd/tweak_rt_limits boolean false" | "${sudo_cmd[@]}" debconf-set-selections
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
