#!/usr/bin/env bash
# The study, rebuilt from measurements in one command: every study (`maille study all`), the
# Bullet peer comparison when its harness is built, the figures (matplotlib), the report page
# filled from the CSV files (scripts/report/report.md.in -> report.md), and the gallery.
# Usage: scripts/report.sh [--quick] [--out DIR]
#   default  data in docs/report/data/, figures in docs/report/figures/, the page docs/report.md,
#            the gallery in docs/gallery/ and docs/gallery.md (what is committed)
#   --quick  shorter sweeps, a quick gallery, everything in out/report-quick/ (for CI: the
#            committed report is left alone); a few minutes on 2 cores
#   --out D  everything in D/ (D/data, D/figures, D/report.md, D/gallery.md, D/gallery/)
# MAILLE_PRESET picks the CMake preset (default release). MAILLE_NO_GALLERY=1 skips the gallery;
# MAILLE_NO_BUILD=1 uses the preset's build as it is. Ctrl-C (or SIGTERM) stops it with exit 130,
# leaving no *.tmp, no half-made data folder, and the previous data in place.
# MAILLE_STUDY_THREADS (default 1): the second thread count of the self-collision scaling and
# the integrators' cost table (the report is measured on one thread: on a shared 2-core machine
# a second thread mostly measures the neighbours).
set -euo pipefail
cd "$(dirname "$0")/.."
quick=() out=
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=(--quick) ;;
    --out) out=$2; shift ;;
    *) echo "usage: scripts/report.sh [--quick] [--out DIR]" >&2; exit 2 ;;
  esac
  shift
done
preset=${MAILLE_PRESET:-release}
if [ -n "$out" ]; then
  data=$out/data figures=$out/figures md=$out/report.md gallery=(--out "$out")
elif [ ${#quick[@]} -gt 0 ]; then
  out=out/report-quick
  data=$out/data figures=$out/figures md=$out/report.md gallery=(--out "$out")
else
  data=docs/report/data figures=docs/report/figures md=docs/report.md gallery=()
fi
# Ctrl-C or SIGTERM: the running child is stopped, the half-made data ($data.new, a run.csv
# being written) removed, the previous data kept (or put back, when the swap below was under
# way), exit 130. Long children run in the background and are waited for, so that the trap runs
# at once rather than when they end.
child=
interrupted() {
  trap - INT TERM
  set +e  # (the child's exit status 130 must not end the clean-up)
  if [ -n "$child" ]; then kill -TERM "$child" 2>/dev/null; wait "$child" 2>/dev/null; fi
  rm -rf "$data.new" "$data/run.csv.tmp"
  if [ -d "$data.old" ]; then
    [ -d "$data" ] || mv "$data.old" "$data"
    rm -rf "$data.old"
  fi
  echo "report: interrupted; the previous data are kept" >&2
  exit 130
}
trap interrupted INT TERM
in_child() {
  "$@" &
  child=$!
  local rc=0
  wait "$child" || rc=$?
  child=
  return $rc
}
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }
start=$(now)

scripts/setup.sh python3-matplotlib
export OMP_WAIT_POLICY=passive
t=$(now)
if [ -z "${MAILLE_NO_BUILD:-}" ]; then  # MAILLE_NO_BUILD=1: the preset's build is up to date
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" --target maille
  # The peer harness is built only where CMake found Bullet (bench/CMakeLists.txt).
  if cmake --build --preset "$preset" --target help 2>/dev/null | grep -q '^peer_bullet\b'; then
    cmake --build --preset "$preset" --target peer_bullet
  fi
fi
build_s=$(since "$t")
maille=build/$preset/apps/maille/maille

t=$(now)
rm -rf "$data.new"
load=$(cut -d' ' -f1 /proc/loadavg)  # the machine's load when the studies start
in_child "$maille" study all --out "$data.new" --threads "${MAILLE_STUDY_THREADS:-1}" "${quick[@]}"
study_s=$(since "$t")

t=$(now)
peer=build/$preset/bench/peer_bullet
peer_s=0 peer_status=absent
if [ -x "$peer" ]; then
  # A failing peer harness costs the report its peer section, not the whole report.
  if in_child "$peer" --out "$data.new" "${quick[@]}"; then peer_status=ran; else
    echo "report: $peer failed (exit $?): the report says so in its peer section" >&2
    peer_status=failed
    rm -f "$data.new/peer.csv"
  fi
  peer_s=$(since "$t")
else
  echo "report: $peer not built (Bullet not found): no peer comparison"
fi
# The CPU-against-GPU table: the GPU backend on whatever EGL finds (llvmpipe when
# there is no GPU, where it is slow: small flags only).
t=$(now)
gpu_s=0 gpu_status=absent
if "$maille" info --backend gpu >/dev/null 2>&1; then
  sizes=64,128,256
  [ ${#quick[@]} -gt 0 ] && sizes=16,32
  steps=()
  [ ${#quick[@]} -gt 0 ] && steps=(--steps 20)
  if in_child scripts/bench_gpu.sh --sizes "$sizes" "${steps[@]}" --maille "$maille" \
       --out "$data.new/gpu/flags.csv" 2>/dev/null; then gpu_status=ran; else gpu_status=failed; fi
  gpu_s=$(since "$t")
fi
# The largest live model per kind: `maille play --benchmark` on one thread by size,
# string, square drum and lattice bar (scripts/bench_live.sh).
t=$(now)
live_status=failed
mkdir -p "$data.new/live"
if in_child scripts/bench_live.sh --maille "$maille" "${quick[@]}" --out "$data.new/live/live.csv"; then
  live_status=ran
else
  rm -f "$data.new/live/live.csv"
fi
live_s=$(since "$t")
# The new data replaces the old only once every study has finished; an interrupt between the
# two moves puts the old back (see interrupted).
rm -rf "$data.old"
if [ -d "$data" ]; then mv "$data" "$data.old"; fi
mv "$data.new" "$data"
rm -rf "$data.old"

t=$(now)
gallery_s=0
if [ -z "${MAILLE_NO_GALLERY:-}" ]; then
  MAILLE_PRESET=$preset MAILLE_NO_BUILD=1 in_child scripts/gallery.sh "${quick[@]}" "${gallery[@]}"
  gallery_s=$(since "$t")
fi

{
  echo "key,value"
  echo "date,$(date -u +%Y-%m-%dT%H:%MZ)"
  echo "commit,$(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "preset,$preset"
  echo "mode,$([ ${#quick[@]} -gt 0 ] && echo quick || echo full)"
  echo "cpu,$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//; s/,//g')"
  echo "cores,$(nproc)"
  echo "load,$load"
  echo "build_s,$build_s"
  echo "study_s,$study_s"
  echo "peer_s,$peer_s"
  echo "peer,$peer_status"
  echo "gpu_s,$gpu_s"
  echo "gpu,$gpu_status"
  echo "live_s,$live_s"
  echo "live,$live_status"
  echo "gallery_s,$gallery_s"
  echo "total_s,$(since "$start")"
} >"$data/run.csv.tmp"
mv "$data/run.csv.tmp" "$data/run.csv"

in_child /usr/bin/python3 scripts/report/report.py --data "$data" --figures "$figures" \
  --template scripts/report/report.md.in --md "$md"
echo "report: $md in $(since "$start") s (build $build_s s, studies $study_s s, peer $peer_s s, gallery $gallery_s s)"
