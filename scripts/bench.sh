#!/usr/bin/env bash
# Benchmarks, written as CSV under bench/results/LABEL-*.csv (LABEL: first argument, default
# the host name). Kernels: Google Benchmark (engine step at 32^2, 128^2, 512^2 on 1 and all
# threads, beside reference loops). Scenes: `maille bench` on every example.
# Compare ratios measured in one run; absolute times only on a quiet machine.
set -euo pipefail
cd "$(dirname "$0")/.."
label=${1:-$(hostname)}
mkdir -p bench/results
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target bench_step maille
# OpenMP's default wait policy on purpose: with OMP_WAIT_POLICY=passive (what the test scripts
# use, because ctest runs two test processes on two cores) every barrier is a futex wake-up,
# measured at ~30 us per barrier and ~50 us per parallel region here, which is more than the
# whole step of a 128^2 flag on two threads. Benchmarks run alone, so spinning is right.
unset OMP_WAIT_POLICY
build/release/bench/bench_step --benchmark_format=csv --benchmark_min_time=1 \
  >"bench/results/$label-kernels.csv"
{
  first=1
  for scene in examples/*.toml; do
    if [ $first = 1 ]; then
      build/release/apps/maille/maille bench "$scene" --steps 2000 --repeat 3
      first=0
    else
      build/release/apps/maille/maille bench "$scene" --steps 2000 --repeat 3 --no-header
    fi
  done
} >"bench/results/$label-scenes.csv"
echo "wrote bench/results/$label-kernels.csv and bench/results/$label-scenes.csv"
