#!/usr/bin/env bash
# cli_scene_run_same.sh MAILLE PYTHON ROOT OUT: the three programs that run a scene file run it
# through one SceneRun (include/maille/scene_run.hpp), so that `maille run`, a case of
# `maille sweep` and the Python module's maille.run() of one scene with one override write the
# same stats.csv: the header byte for byte (every column, ns_* included), and every row byte for
# byte but for the ns_* columns, which are the wall-clock time each stage took in that step
# (two runs of the same program differ there too).
set -u
maille=$1 python=$2 root=$3 out=$4
scene=$root/examples/flag_in_wind.toml
key="flag[0].stiffness" value=800.0 duration=0.25
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
without_timings() {  # the CSV without its ns_* columns
  awk -F, 'NR==1{for(i=1;i<=NF;i++) keep[i]=($i !~ /^ns_/)} {s=""; for(i=1;i<=NF;i++) if(keep[i]) s=s","$i; print s}' "$1"
}

"$maille" run "$scene" --set "$key=$value" --duration $duration --threads 1 --no-frames \
  --out "$out/run" >"$out/run.log" 2>&1 || { cat "$out/run.log"; fail "maille run"; }

cat >"$out/sweep.toml" <<END
scene = "$scene"
duration = $duration
[axes]
"$key" = [$value]
END
"$maille" sweep "$out/sweep.toml" --out "$out/sweep" --threads 1 >"$out/sweep.log" 2>&1 \
  || { cat "$out/sweep.log"; fail "maille sweep"; }

"$python" -c "
import sys, maille
r = maille.run(sys.argv[1], {sys.argv[2]: float(sys.argv[3])}, out=sys.argv[4],
               duration=float(sys.argv[5]), threads=1, frames=False)
print(r)
" "$scene" "$key" "$value" "$out/python" "$duration" >"$out/python.log" 2>&1 \
  || { cat "$out/python.log"; fail "maille.run"; }

run=$out/run/stats.csv
rows=$(($(wc -l <"$run") - 1))
[ "$rows" -eq 8 ] || fail "$run has $rows rows, expected 8 (1000 steps, a sample every 133)"
for other in "$out/sweep/cases/0000/stats.csv" "$out/python/stats.csv"; do
  [ -s "$other" ] || fail "no $other"
  cmp <(head -1 "$run") <(head -1 "$other") || fail "the header of $other differs from $run"
  cmp <(without_timings "$run") <(without_timings "$other") \
    || fail "$other differs from $run (ns_* columns left out)"
done
echo "maille run, a sweep case and maille.run(): the same stats.csv ($rows rows, $(head -1 "$run" | tr ',' '\n' | wc -l) columns, ns_* timings left out of the rows)"
