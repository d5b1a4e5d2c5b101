#!/usr/bin/env bash
# ctest peer.bullet_quick_csv: peer_bullet --quick writes peer.csv with the agreed columns, and
# both engines have rows (32^2 and 64^2, default and tuned).
#   check_peer.sh PEER_BULLET OUTDIR
set -euo pipefail
exe=$1 out=$2
rm -rf "$out"
"$exe" --quick --out "$out"
csv=$out/peer.csv
test -f "$csv" || { echo "no $csv"; exit 1; }
test ! -e "$csv.tmp" || { echo "temporary file left behind"; exit 1; }
want="engine,version,particles,setting,step_s,wall_s_per_sim_s,max_penetration_m,max_stretch,stable"
head -1 "$csv" | grep -q "^$want" || { echo "bad header: $(head -1 "$csv")"; exit 1; }
for engine in maille bullet; do
  for particles in 1024 4096; do
    for setting in default tuned; do
      grep -q "^$engine,[^,]*,$particles,$setting," "$csv" ||
        { echo "no row for $engine $particles $setting"; cat "$csv"; exit 1; }
    done
  done
done
# Every row has the header's column count; stable is 0 or 1; numbers are numbers.
awk -F, 'NR == 1 { n = NF; next }
  NF != n { print "row " NR ": " NF " columns, header has " n; bad = 1 }
  $9 != 0 && $9 != 1 { print "row " NR ": stable is " $9; bad = 1 }
  $5 + 0 <= 0 || $6 + 0 <= 0 { print "row " NR ": step or wall time not positive"; bad = 1 }
  END { exit bad }' "$csv"
echo "peer.csv: $(($(wc -l < "$csv") - 1)) rows"
