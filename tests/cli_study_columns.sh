#!/usr/bin/env bash
# `maille study integrators --quick`: every row of every CSV has as many fields as its header
# and crossover.csv has leapfrog's limit in its column (it once went to wall_s_per_simulated_s).
set -u
maille=$1 out=$2
rm -rf "$out"
timeout 300 "$maille" study integrators --quick --out "$out" >"$out.log" 2>&1 || { cat "$out.log"; exit 1; }
for f in "$out"/*.csv; do
  awk -F, 'NR == 1 { n = NF } NF != n { printf "%s:%d: %d fields, header has %d\n", FILENAME, NR, NF, n; bad = 1 }
           END { exit bad }' "$f" || exit 1
done
# crossover.csv: leapfrog's limit is in its own column on every row, implicit Euler's included.
awk -F, 'NR > 1 && $4 == "" { printf "crossover.csv:%d: no leapfrog_limit_s\n", NR; bad = 1 }
         END { exit bad }' "$out/crossover.csv" || exit 1
echo "every row has its header's field count: $(ls "$out"/*.csv | wc -l) files"
