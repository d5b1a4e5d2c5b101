#!/usr/bin/env bash
# The largest live model per kind (the report's "Playing live" section, docs/sound.md):
# `maille play --benchmark` on one thread, 48 kHz, 64-frame periods, for a string (rope with
# fixed ends, examples/play_string.toml's bead and spacing), a square drum
# (bench/scenes/play_square_drum.toml) and a lattice bar (bench/scenes/play_lattice_bar.toml) at
# growing sizes: the step's CPU time per period (CLOCK_THREAD_CPUTIME_ID) as a fraction of the
# period, mean, p99 and largest. A size is live when its p99 is at most half the period.
#   scripts/bench_live.sh [--maille BIN] [--duration S] [--quick] [--out FILE.csv]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
maille="$here/build/release/apps/maille/maille"
duration=2
out=/dev/stdout
strings=(64 128 256 512 1024 2048)
sides=(8 12 16 24 32 40)
bars=(6 10 20 40 80)
while [ $# -gt 0 ]; do
  case "$1" in
    --maille) maille=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --quick) duration=0.5 strings=(64 256) sides=(8 16) bars=(6 20); shift ;;
    *) echo "bench_live.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
export OMP_WAIT_POLICY=passive
py() { python3 -c "print($1)"; }

# kind size scene sets...: one CSV row.
measure() {
  local kind=$1 size=$2 scene=$3
  shift 3
  local counts line
  counts=$("$maille" validate "$scene" "$@" | head -1)
  line=$("$maille" play "$scene" --benchmark --duration "$duration" --threads 1 "$@")
  python3 - "$kind" "$size" "$counts" "$line" <<'PY'
import re, sys
kind, size, counts, line = sys.argv[1:5]
points = re.search(r"\((\d+) points", counts).group(1)
links = re.search(r"(\d+) links", counts).group(1)
m = re.search(r"mean ([\d.]+) %, p99 ([\d.]+) %, largest ([\d.]+) %", line)
blown = "BLEW UP" in line
print(",".join([kind, size, points, links] + [f"{float(x) / 100:.4f}" for x in m.groups()] +
               ["blew_up" if blown else "ok"]))
PY
}

{
  echo "kind,size,points,links,cpu_mean,cpu_p99,cpu_largest,status"
  for n in "${strings[@]}"; do
    measure string "$n" "$here/examples/play_string.toml" --set "rope[0].points=$n" \
      --set "rope[0].end=[$(py "0.65 / 31 * ($n - 1)"),0,0]" --set "rope[0].mass=$(py "0.0001 * $n")"
  done
  for n in "${sides[@]}"; do
    at=$(((n / 2) * n + n / 3))
    w=$(py "0.3 / 13 * ($n - 1)")
    measure drum "$n" "$here/bench/scenes/play_square_drum.toml" --set "net[0].resolution=[$n,$n]" \
      --set "net[0].width=$w" --set "net[0].depth=$w" --set "net[0].mass=$(py "0.05 / 523 * $n * $n")" \
      --set "listen[0].point=skin:$at" --set "control[0].excite.point=skin:$at"
  done
  for n in "${bars[@]}"; do
    measure bar "$n" "$here/bench/scenes/play_lattice_bar.toml" --set "lattice[0].resolution=[$n,3,3]" \
      --set "lattice[0].size=[$(py "0.02 * ($n - 1)"),0.04,0.04]" --set "lattice[0].mass=$(py "0.009 * $n")" \
      --set "listen[0].point=bar:$((9 * n - 1))"
  done
} >"$out"
