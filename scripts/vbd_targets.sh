#!/usr/bin/env bash
# VBD's performance targets, measured in one run (docs/implicit.md, "The issue's speed
# targets"): each part writes its raw output to OUT/ and prints what it measured.
#   sweep    BM_VbdSweep at 128^2 (and 64^2): ns per point per sweep, scalar and each width the
#            CPU runs (bench_step)
#   peer     the cloth on the sphere at 1/60 s by VBD at several sweep counts beside Bullet
#            tuned's ladder, 64^2 and 128^2, 1 s simulated (peer_bullet --large-steps)
#   drape    examples/cloth_on_sphere.toml's drape (as cloth_on_sphere_vbd: implicit Euler, VBD,
#            the thin self-contact layer) at 64^2 and 128^2, two threads, 3 s simulated, at each
#            (step, sweeps) of DRAPE_64 / DRAPE_128: wall s per simulated s with the largest
#            stretch, depth and crossing pairs (drape_quality). At 128^2 the layer's radius is
#            DRAPE_128_RADIUS (default 0.002 m, a quarter of the spacing as the example's 8 mm is
#            of 32^2's): 8 mm is the whole spacing there, every point is in two-body contacts
#            with its neighbours' faces, the coarse correction leaves them to the sweeps, and the
#            cloth stays in the air (at 1/60 s, 10 sweeps: 33 % stretch, never touching the ball)
#   explicit the explicit step of the flag and cloth examples, one thread, this build against
#            BASE's maille when BASE is set, alternating, the fastest of ROUNDS (default 5), two
#            ways: `maille bench` (the step alone: no energy sample, no stats row) and `maille run
#            --no-frames` (the scene's stats cadence, where the energies, contacts' included, are
#            sampled, and the runaway watch)
# Usage: scripts/vbd_targets.sh [--out DIR] [PART...]   (default: every part; out/vbd-targets)
# MAILLE_PRESET picks the build (default dev, what docs/implicit.md's tables used); BASE=path to
# another build's maille for the explicit part's before/after. Builds are not started here:
# build first (cmake --build --preset dev), and run this when the machine is quiet.
set -euo pipefail
cd "$(dirname "$0")/.."
out=out/vbd-targets parts=()
while [ $# -gt 0 ]; do
  case $1 in
    --out) out=$2; shift ;;
    sweep|peer|drape|explicit) parts+=("$1") ;;
    *) echo "usage: scripts/vbd_targets.sh [--out DIR] [sweep|peer|drape|explicit]..." >&2; exit 2 ;;
  esac
  shift
done
[ ${#parts[@]} -gt 0 ] || parts=(sweep peer drape explicit)
preset=${MAILLE_PRESET:-dev}
build=build/$preset
export OMP_WAIT_POLICY=passive
mkdir -p "$out"
echo "vbd_targets: $(date -u +%FT%TZ), commit $(git rev-parse --short HEAD), load $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores" | tee "$out/when.txt"

for part in "${parts[@]}"; do
  case $part in
    sweep)
      "$build/bench/bench_step" --benchmark_filter='BM_VbdSweep/(64|128)/' \
        --benchmark_min_time=1 --benchmark_format=csv 2>/dev/null | tee "$out/sweep.csv"
      ;;
    peer)
      "$build/bench/peer_bullet" --out "$out/peer" --sizes "${PEER_SIZES:-64,128}" \
        --duration "${PEER_DURATION:-1}" --large-steps --rates "${PEER_RATES:-60}" \
        --sweeps "${PEER_SWEEPS:-6,8,10,15,20}" --settings bullet.tuned | tee "$out/peer.log"
      ;;
    drape)
      : >"$out/drape.csv"
      for spec in "64:${DRAPE_64:-60/10 30/6 20/6}" "128:${DRAPE_128:-60/10 30/6 20/6}"; do
        n=${spec%%:*} radius=()
        [ "$n" = 128 ] && radius=(--set "self_collision.radius=${DRAPE_128_RADIUS:-0.002}")
        for hs in ${spec#*:}; do
          per=${hs%/*} sweeps=${hs#*/}
          h=$(awk -v p="$per" 'BEGIN { printf "%.17g", 1 / p }')
          row=$("$build/bench/drape_quality" examples/cloth_on_sphere_vbd.toml --threads 2 \
            --set "flag[0].resolution=[$n,$n]" --set "simulation.step=$h" \
            --set "simulation.implicit.iterations=$sweeps" "${radius[@]}" || true)
          [ -s "$out/drape.csv" ] || echo "$row" | head -1 >"$out/drape.csv"
          echo "$row" | tail -1 | tee -a "$out/drape.csv"
        done
      done
      ;;
    explicit)
      rounds=${ROUNDS:-5}
      echo "build,scene,round,mode,ns_per_particle_step" >"$out/explicit.csv"
      builds=("$build/apps/maille/maille")
      [ -n "${BASE:-}" ] && builds=("$BASE" "${builds[@]}")
      for r in $(seq "$rounds"); do
        for scene in flag_in_wind flag_64 shaken_flag cloth_on_sphere cloth_heap two_cloths; do
          for m in "${builds[@]}"; do
            steps=${EXPLICIT_STEPS:-5000}
            ns=$("$m" bench "examples/$scene.toml" --steps "$steps" --warmup 200 \
              --repeat 1 --threads 1 --backend cpu --no-header | cut -d, -f7)
            echo "$m,$scene,$r,bench,$ns" | tee -a "$out/explicit.csv"
            ns=$("$m" run "examples/$scene.toml" --steps "$steps" --threads 1 --backend cpu \
              --no-frames --out "$out/run-tmp" 2>&1 | sed -n 's/.* wall, \([0-9.e+]*\) ns per particle-step.*/\1/p')
            echo "$m,$scene,$r,run,$ns" | tee -a "$out/explicit.csv"
          done
        done
      done
      rm -rf "$out/run-tmp"
      ;;
  esac
done
