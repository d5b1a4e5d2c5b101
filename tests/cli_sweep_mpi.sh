#!/usr/bin/env bash
# cli_sweep_mpi.sh MAILLE SWEEP OUT: `maille sweep` under mpirun.
#  - 2 and 3 ranks give the summary of one process (every column but wall_seconds, rank, ns_*),
#    with cases run by more than one rank (rank 0 included);
#  - one slow case does not hold the others back: its rank runs it alone while the other rank
#    runs the 7 others (cases are handed out one at a time);
#  - a rank killed (SIGKILL) mid-sweep: the job dies; the same command completes the sweep,
#    runs only the cases without a done marker, and ends with the same summary;
#  - SIGTERM to every rank (what Slurm's scancel sends): the ranks finish their current cases,
#    the summary lists every case done, exit 130; the same command completes it.
# Skipped (exit 77) without mpirun or when this maille was built without MPI.
set -u
maille=$1 sweep=$2 out=$3
here=$(dirname "$0")
command -v mpirun >/dev/null || { echo "SKIP: no mpirun (scripts/setup.sh installs openmpi-bin)"; exit 77; }
mpirun=(mpirun --allow-run-as-root --oversubscribe)
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
compare() { /usr/bin/python3 "$here/sweep_compare.py" "$out/one/summary.csv" "$1/summary.csv" || fail "$2"; }
ranks_used() {
  /usr/bin/python3 -c 'import csv,sys; print(len({r["rank"] for r in csv.DictReader(open(sys.argv[1]))}))' "$1"
}
markers() { ls "$1"/cases/*/done 2>/dev/null | wc -l; }
# wait_markers DIR N: until N cases are done in DIR (at most 10 s)
wait_markers() { for _ in $(seq 400); do [ "$(markers "$1")" -ge "$2" ] && return; sleep 0.025; done; }

"$maille" sweep "$sweep" --out "$out/one" --threads 1 >"$out/one.log" 2>&1 \
  || { cat "$out/one.log"; fail "one-process sweep"; }
total=$(markers "$out/one")

for n in 2 3; do
  timeout 300 "${mpirun[@]}" -n $n "$maille" sweep "$sweep" --out "$out/n$n" --threads 1 \
    >"$out/n$n.log" 2>&1
  rc=$?
  cat "$out/n$n.log"
  if grep -q "built without MPI" "$out/n$n.log"; then
    echo "SKIP: this maille was built without MPI"
    exit 77
  fi
  [ $rc -eq 0 ] || fail "mpirun -n $n: exit $rc"
  compare "$out/n$n" "mpirun -n $n: the summary differs from one process's"
  used=$(ranks_used "$out/n$n/summary.csv")
  [ "$used" -ge 2 ] || fail "mpirun -n $n: cases ran on $used rank(s) only"
  echo "mpirun -n $n: the same summary, cases on $used ranks"
done

# Dynamic hand-out: one slow case (a step 50 times smaller) does not hold the others back; the
# rank that runs it runs nothing else while the other rank runs every other case.
cat >"$out/slow.toml" <<EOF
scene = "$(cd "$(dirname "$sweep")/../../../examples" && pwd)/pendulum_chain.toml"
duration = 0.5
[axes]
"simulation.step" = [2e-6, 1e-4, 1.1e-4, 1.2e-4, 1.3e-4, 1.4e-4, 1.5e-4, 1.6e-4]
EOF
timeout 300 "${mpirun[@]}" -n 2 "$maille" sweep "$out/slow.toml" --out "$out/slow" --threads 1 \
  >"$out/slow.log" 2>&1 || { cat "$out/slow.log"; fail "the sweep with a slow case"; }
counts=$(/usr/bin/python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
slow = rows[0]["rank"]
print(sum(r["rank"] == slow for r in rows), sum(r["rank"] != slow for r in rows))
' "$out/slow/summary.csv")
[ "$counts" = "1 7" ] || fail "slow case: its rank ran $counts (that rank, the other): expected 1 7"
echo "a slow case ran alone on its rank while the other rank ran the 7 others"

# A rank killed mid-sweep: the job dies; the same command completes it.
"${mpirun[@]}" -n 2 "$maille" sweep "$sweep" --out "$out/kill" --threads 1 >"$out/kill.log" 2>&1 &
job=$!
wait_markers "$out/kill" 2
victim=$(pgrep -P $job | tail -1)
[ -n "$victim" ] || fail "no rank process under mpirun $job"
kill -KILL "$victim"
wait $job
rc=$?
[ $rc -ne 0 ] || fail "mpirun exited 0 with a rank killed"
done_before=$(markers "$out/kill")
# The other ranks run on until mpirun ends them: rarely (the rank killed between two cases)
# every case is done, and the resume below has nothing to run.
[ "$done_before" -lt "$total" ] || echo "note: every case was done before the job ended"
mkdir -p "$out/kill_markers"
for f in "$out"/kill/cases/*/done; do cp "$f" "$out/kill_markers/$(basename "$(dirname "$f")")"; done
timeout 300 "${mpirun[@]}" -n 2 "$maille" sweep "$sweep" --out "$out/kill" --threads 1 \
  >"$out/kill_resume.log" 2>&1 || { cat "$out/kill_resume.log"; fail "resume after the kill"; }
cat "$out/kill_resume.log"
grep -q "$done_before of $total cases already done" "$out/kill_resume.log" \
  || fail "the resume did not skip the $done_before cases done"
# The cases done before the kill did not run again: their markers are untouched.
for f in "$out"/kill_markers/*; do
  cmp -s "$f" "$out/kill/cases/$(basename "$f")/done" || fail "case $(basename "$f") ran again"
done
compare "$out/kill" "the summary after a killed rank and a resume differs"
echo "rank killed after $done_before of $total cases; resumed to the same summary"

# SIGTERM to every rank: the current cases finish, exit 130, the summary lists them.
"${mpirun[@]}" -n 2 "$maille" sweep "$sweep" --out "$out/term" --threads 1 >"$out/term.log" 2>&1 &
job=$!
wait_markers "$out/term" 2
kill -TERM $(pgrep -P $job)
wait $job
rc=$?
cat "$out/term.log"
[ $rc -eq 130 ] || fail "exit $rc after SIGTERM to the ranks, expected 130"
done_before=$(markers "$out/term")
rows=$(($(wc -l <"$out/term/summary.csv") - 1))
[ "$rows" -eq "$done_before" ] || fail "$rows summary rows for $done_before cases done"
[ -z "$(find "$out/term" -name '*.tmp')" ] || fail "temporary files left after SIGTERM"
timeout 300 "${mpirun[@]}" -n 2 "$maille" sweep "$sweep" --out "$out/term" --threads 1 \
  >"$out/term_resume.log" 2>&1 || { cat "$out/term_resume.log"; fail "resume after SIGTERM"; }
compare "$out/term" "the summary after SIGTERM and a resume differs"
echo "SIGTERM after $done_before of $total cases (exit 130); resumed to the same summary"
