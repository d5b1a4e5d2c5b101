#!/usr/bin/env bash
# cli_sweep.sh MAILLE DATA OUT: `maille sweep` in one process.
#  - chain.toml (2 x 2 cases): exit 0, summary.csv with its columns and one row per case in the
#    order of the axes' product, DIR/cases/<id>/stats.csv and done, nothing .tmp;
#  - each case's stats.csv equals `maille run` of the scene with the same --set and --duration
#    (every column but the ns_* timings);
#  - a rerun skips every case and rewrites the same summary;
#  - [output] frames = true writes the frames of each case;
#  - rows.toml: a blow-up and a bad value are rows (blowup 3, error 1), the sweep exits 0.
set -u
maille=$1 data=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
physics() {  # a CSV without its ns_* columns
  awk -F, 'NR==1{for(i=1;i<=NF;i++) keep[i]=($i !~ /^ns_/)} {s=""; for(i=1;i<=NF;i++) if(keep[i]) s=s","$i; print s}' "$1"
}

"$maille" sweep "$data/chain.toml" --out "$out/chain" --threads 1 >"$out/chain.log" 2>&1 \
  || { cat "$out/chain.log"; fail "sweep exit $?"; }
cat "$out/chain.log"
summary=$out/chain/summary.csv
head -1 "$summary" | grep -q '^case,rope\[0\]\.stiffness,simulation\.step,status,exit_code,message,rank,wall_seconds,simulated_seconds,final_energy,time,step,kinetic,elastic,gravity,contact,total' \
  || fail "summary header: $(head -1 "$summary")"
[ "$(cut -d, -f1-5 "$summary" | tail -n +2 | tr '\n' ' ')" = \
  "0000,2000.0,1e-04,ok,0 0001,2000.0,2e-04,ok,0 0002,5000.0,1e-04,ok,0 0003,5000.0,2e-04,ok,0 " ] \
  || fail "summary rows: $(cut -d, -f1-5 "$summary")"
for id in 0000 0001 0002 0003; do
  [ -s "$out/chain/cases/$id/stats.csv" ] || fail "no cases/$id/stats.csv"
  [ -s "$out/chain/cases/$id/done" ] || fail "no cases/$id/done"
done
[ -z "$(find "$out/chain" -name '*.tmp')" ] || fail "temporary files left"

# The same trajectory as `maille run`: case 0003 is stiffness 5000, step 2e-4.
"$maille" run "$data/../../../examples/pendulum_chain.toml" --set rope[0].stiffness=5000.0 \
  --set simulation.step=2e-4 --duration 0.2 --threads 1 --no-frames --out "$out/run" >/dev/null \
  || fail "maille run"
diff <(physics "$out/run/stats.csv") <(physics "$out/chain/cases/0003/stats.csv") \
  || fail "case 0003's stats.csv differs from maille run's"

# A rerun skips every case; the summary is the same but for nothing.
cp "$summary" "$out/first.csv"
"$maille" sweep "$data/chain.toml" --out "$out/chain" >"$out/rerun.log" 2>&1 || fail "rerun"
grep -q "4 of 4 cases already done" "$out/rerun.log" || fail "rerun: $(cat "$out/rerun.log")"
cmp -s "$summary" "$out/first.csv" || fail "the rerun changed the summary"

# Frames on request.
cat >"$out/frames.toml" <<EOF
scene = "$data/../../../examples/pendulum_chain.toml"
duration = 0.1
[axes]
"rope[0].damping" = [0.05, 0.1]
[output]
frames = true
EOF
"$maille" sweep "$out/frames.toml" --out "$out/frames" >/dev/null 2>&1 || fail "frames sweep"
[ -s "$out/frames/cases/0001/frame_000000.ply" ] || fail "no frames in cases/0001"
[ -s "$out/frames/cases/0001/frame_000005.ply" ] || fail "frames/cases/0001 lacks frame 5"

# Cases that fail are rows.
"$maille" sweep "$data/rows.toml" --out "$out/rows" >"$out/rows.log" 2>&1 \
  || { cat "$out/rows.log"; fail "a sweep with failing cases must exit 0"; }
cat "$out/rows.log"
rows=$(/usr/bin/python3 -c '
import csv, sys
for r in csv.DictReader(open(sys.argv[1])):
    print(r["case"], r["status"], r["exit_code"], "energy" if r["final_energy"] else "-", r["message"])
' "$out/rows/summary.csv") || fail "summary unreadable"
echo "$rows"
grep -q "^0000 ok 0 energy $" <<<"$rows" || fail "case 0000 should be ok"
grep -q "^0001 blowup 3 - blow-up detected at step" <<<"$rows" || fail "case 0001 should blow up"
grep -q "^0002 error 1 - .*pendulum_chain.toml (--set): err" <<<"$rows" || fail "case 0002 is a bad value"
grep -q "^0003 error 1 - " <<<"$rows" || fail "case 0003 is a bad value"
echo "sweep in one process: summary, cases, maille run's trajectory, rerun, frames, failing rows"
