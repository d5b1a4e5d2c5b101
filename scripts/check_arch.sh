#!/usr/bin/env bash
# Compile-only check, warnings as errors, for the x86-64 micro-architecture levels v2, v3 and v4
# (SSE4.2; AVX2; AVX-512): a CPU the developers do not have must not break the build. Nothing is
# run.
#
# By default only the translation units whose text depends on the level are compiled: those
# that test an instruction-set macro (__SSE*, __AVX*), include <immintrin.h> or use
# target_clones, and every file that includes one of them, followed through includes to the
# .cpp files (found here by name, so a new one is checked without editing this script). Every
# other unit compiles the same source at every level (the project builds with
# -ffp-contract=off; Eigen's own vectorisation is a system header's), and the `dev` build
# already compiles it, warnings as errors. Compiling the whole engine three times cost about
# 1,700 s of compile time per level by the build logs (about 40 minutes on 2 cores, of a CI run
# of 64) for those few files.
# Usage: scripts/check_arch.sh [--all] [v2 v3 v4]
#   --all  compile the engine libraries and the command line at each level (the former check)
set -euo pipefail
cd "$(dirname "$0")/.."
all=0
if [ "${1:-}" = "--all" ]; then all=1; shift; fi
levels=("${@:-v2 v3 v4}")

# The .cpp files whose preprocessed text depends on the instruction set, by include closure.
arch_sources() {
  python3 - <<'EOF'
import pathlib, re
roots = [pathlib.Path(p) for p in ("src", "include", "apps", "python")]
files = [f for r in roots if r.exists() for f in r.rglob("*")
         if f.suffix in (".cpp", ".hpp", ".h", ".inl")]
text = {f: f.read_text(errors="replace") for f in files}
marks = re.compile(r"__(SSE|AVX)[0-9A-Z_]*__|immintrin\.h|target_clones|__builtin_cpu_supports")
include = re.compile(r'#\s*include\s*[<"]([^">]+)[">]')
hot = {f for f, t in text.items() if marks.search(t)}
while True:
    names = {f.name for f in hot}
    more = {f for f, t in text.items() if f not in hot
            and any(pathlib.PurePath(i).name in names for i in include.findall(t))}
    if not more:
        break
    hot |= more
for f in sorted(hot):
    if f.suffix == ".cpp":
        print(f)
EOF
}

for level in ${levels[@]}; do
  echo "check_arch: -march=x86-64-$level"
  cmake --preset "arch-$level" >/dev/null
  if [ "$all" = 1 ]; then
    cmake --build --preset "arch-$level"
    continue
  fi
  dir=build/arch-$level
  # The object file of each such source, from the compile database (a source outside the
  # configured targets, such as the Python module's, is skipped).
  mapfile -t objects < <(arch_sources | python3 -c '
import json, os, sys
wanted = {os.path.abspath(l.strip()) for l in sys.stdin if l.strip()}
for c in json.load(open(sys.argv[1])):
    if os.path.abspath(c["file"]) in wanted:
        print(c["command"].split(" -o ")[1].split()[0])' "$dir/compile_commands.json")
  [ "${#objects[@]}" -gt 0 ] || { echo "check_arch: no arch-dependent sources found" >&2; exit 1; }
  echo "check_arch: ${#objects[@]} translation units"
  ninja -C "$dir" "${objects[@]}"
done
