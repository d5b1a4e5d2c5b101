#!/usr/bin/env bash
# Fuzzes the scene reader and the model checks (fuzz/fuzz_scene.cpp) with libFuzzer, ASan and
# UBSan. Seeds: examples/*.toml and tests/data/bad/*.toml; dictionary: fuzz/scene.dict.
# Usage: scripts/fuzz.sh [--quick]
#   --quick  about 60 s in all (CI)
#   default  10^6 executions (-runs=1000000), a few minutes to half an hour on 2 cores
# Findings (crash-*, leak-*, timeout-*, oom-*) are written to build/fuzz/findings/; the corpus
# grows in build/fuzz/corpus/ (not committed). Each crash becomes a file in tests/data/bad/.
# Inputs that only run slowly or use much memory (huge sizes, tiny steps) stop at
# -timeout=10 / -rss_limit_mb=2048 and are reported, not fixed here (scene size limits). Valid
# models above 20k points + links are read and built but not simulated (fuzz_scene.cpp).
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1
scripts/setup.sh clang
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
out=build/fuzz
mkdir -p "$out/corpus" "$out/findings"
common=(-dict=fuzz/scene.dict -timeout=10 -rss_limit_mb=2048 -max_len=8192
        -artifact_prefix="$out/findings/" -print_final_stats=1)
seeds=(examples tests/data)  # read recursively: tests/data/bad and the unstable spring
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 OMP_WAIT_POLICY=passive
if [ "$quick" = 1 ]; then
  "$out/fuzz/fuzz_scene" "${common[@]}" -max_total_time=60 "$out/corpus" "${seeds[@]}"
else
  "$out/fuzz/fuzz_scene" "${common[@]}" -runs=1000000 "$out/corpus" "${seeds[@]}"
fi
