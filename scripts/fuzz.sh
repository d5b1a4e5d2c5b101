#!/usr/bin/env bash
# Fuzzes with libFuzzer, ASan and UBSan:
#   fuzz_scene  the scene reader and the model checks (fuzz/fuzz_scene.cpp). Seeds: examples/
#               and tests/data/ (recursively); dictionary: fuzz/scene.dict.
#   fuzz_mesh   the OBJ and STL readers (fuzz/fuzz_mesh.cpp). Seeds: tests/data/meshes/ and
#               examples/models/; dictionary: fuzz/mesh.dict.
# Usage: scripts/fuzz.sh [--quick]
#   --quick  about 60 s in all (CI): 40 s scene, 20 s mesh
#   default  10^6 executions of each (-runs=1000000), a few minutes to half an hour on 2 cores
# Findings (crash-*, leak-*, timeout-*, oom-*; mesh-* for fuzz_mesh) are written to
# build/fuzz/findings/; the corpora grow in build/fuzz/corpus/ and build/fuzz/corpus_mesh/ (not
# committed). Each crash becomes a file in tests/data/bad/ (scenes) or tests/data/meshes/bad/.
# Inputs that only run slowly or use much memory (huge sizes, tiny steps) stop at
# -timeout=10 / -rss_limit_mb=2048 and are reported, not fixed here (scene size limits). Valid
# models above 20k points + links are read and built but not simulated, and fuzz_scene runs
# under a 32 MiB memory budget (MAILLE_MEMORY_BUDGET, unless set), which bounds the work stages
# do when built (a conditional obstacle's sampling): fuzz_scene.cpp.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1
scripts/setup.sh clang
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
out=build/fuzz
mkdir -p "$out/corpus" "$out/corpus_mesh" "$out/findings"
common=(-timeout=10 -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1)
scene=(-dict=fuzz/scene.dict -artifact_prefix="$out/findings/" "$out/corpus" examples tests/data)
mesh=(-dict=fuzz/mesh.dict -artifact_prefix="$out/findings/mesh-" "$out/corpus_mesh"
      tests/data/meshes examples/models)
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 OMP_WAIT_POLICY=passive
if [ "$quick" = 1 ]; then
  "$out/fuzz/fuzz_scene" "${common[@]}" -max_total_time=40 "${scene[@]}"
  "$out/fuzz/fuzz_mesh" "${common[@]}" -max_total_time=20 "${mesh[@]}"
else
  "$out/fuzz/fuzz_scene" "${common[@]}" -runs=1000000 "${scene[@]}"
  "$out/fuzz/fuzz_mesh" "${common[@]}" -runs=1000000 "${mesh[@]}"
fi
