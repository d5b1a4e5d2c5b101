#!/usr/bin/env bash
# Maille in the browser (docs/web.md): the engine compiled to WebAssembly by Debian's emscripten
# and the playground page, laid out in build/web/.
#   scripts/web.sh                  builds build/web/ (index.html, maille.js, maille.wasm, ...)
#   scripts/web.sh serve [--port N] [--no-isolation]
#                                   builds when needed, then serves build/web on 127.0.0.1:8000
#                                   with the cross-origin isolation headers (threads)
#   scripts/web.sh test             the browser test: Debian's Chromium, headless, driven by
#                                   playwright-core (web/tests/browser_test.mjs)
#   scripts/web.sh bench            WebAssembly against native time per step (web/tests/bench.mjs)
# Set-up: scripts/setup.sh web (emscripten, chromium, nodejs, npm); npm ci in web/ for the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
mode=build
case "${1:-}" in
  serve|test|bench) mode=$1; shift ;;
  build) shift ;;
  "") ;;
  *) echo "usage: scripts/web.sh [build | serve [--port N] [--no-isolation] | test | bench]" >&2; exit 2 ;;
esac

scripts/setup.sh web
# Debian's em++ at -O2 and above runs Node.js tools that need Debian's node modules.
export NODE_PATH=/usr/share/nodejs

# Two modules from the same sources (docs/web.md, "Threads"): maille.js on one thread (build/wasm)
# and maille-mt.js, OpenMP on Web Workers (build/wasm-mt), which the page runs when it is served
# cross-origin isolated. MAILLE_WEB_THREADS=0 builds the first only (the page falls back to it).
build() {
  emcmake cmake -S . -B build/wasm -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DMAILLE_WEB_OUTPUT="$root/build/web" >/dev/null
  cmake --build build/wasm --target maille_web -j "${MAILLE_WEB_JOBS:-2}"
  if [ "${MAILLE_WEB_THREADS:-1}" != 0 ]; then
    emcmake cmake -S . -B build/wasm-mt -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DMAILLE_WEB_THREADS=ON -DMAILLE_WEB_OUTPUT="$root/build/web" >/dev/null
    cmake --build build/wasm-mt --target maille_web -j "${MAILLE_WEB_JOBS:-2}"
  else
    rm -f build/web/maille-mt.js build/web/maille-mt.wasm build/web/maille-mt.worker.js
  fi
  mkdir -p build/web/gallery
  cp web/page/* build/web/
  # The shared smooth-surface math, pasted into the page's WebGL2 shader (render.js) as the
  # renderer pastes it into its compute shader (src/render/smooth_shader.hpp).
  cp include/maille/detail/smooth_math.glsl build/web/
  cp docs/gallery/*.png build/web/gallery/
  # The page asks only for the pictures listed here (an example without one gets none).
  (cd docs/gallery && ls *.png | sed 's/\.png$//' |
    python3 -c 'import json, sys; print(json.dumps(sys.stdin.read().split()))') \
    >build/web/gallery/index.json
  echo "web.sh: build/web/ is ready (scripts/web.sh serve, then http://127.0.0.1:8000/)"
}

npm_ready() {
  if [ ! -d web/node_modules/playwright-core ]; then
    (cd web && npm ci --no-audit --no-fund --loglevel=error)
  fi
}

case "$mode" in
  build) build ;;
  serve)
    [ -f build/web/maille.wasm ] || build
    exec python3 web/serve.py --dir build/web "$@" ;;
  test)
    build
    npm_ready
    node web/tests/browser_test.mjs "$@" ;;
  bench)
    build
    npm_ready
    node web/tests/bench.mjs "$@" ;;
esac
