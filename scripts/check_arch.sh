#!/usr/bin/env bash
# Compile-only check, warnings as errors, for the x86-64 micro-architecture levels v2, v3 and v4
# (SSE4.2; AVX2; AVX-512): a CPU the developers do not have must not break the build. Only the
# engine libraries and the command line are compiled (no renderer, tests or benchmarks: the
# arch-sensitive code is the engine's); nothing is run.
# Usage: scripts/check_arch.sh [v2 v3 v4]
set -euo pipefail
cd "$(dirname "$0")/.."
levels=("${@:-v2 v3 v4}")
for level in ${levels[@]}; do
  echo "check_arch: -march=x86-64-$level"
  cmake --preset "arch-$level" >/dev/null
  cmake --build --preset "arch-$level"
done
