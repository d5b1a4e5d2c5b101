#!/usr/bin/env bash
# `maille study validity`: every analytic case within its tolerance (the table the report uses).
set -u
maille=$1 out=$2
rm -rf "$out"
"$maille" study validity --out "$out" >/dev/null || { echo "study failed"; exit 1; }
[ -s "$out/validity.csv" ] || { echo "validity.csv missing"; exit 1; }
head -1 "$out/validity.csv" | grep -q "^case,quantity,analytic,measured,relative_error,tolerance$" \
  || { echo "bad header: $(head -1 "$out/validity.csv")"; exit 1; }
rows=$(($(wc -l <"$out/validity.csv") - 1))
[ "$rows" -ge 6 ] || { echo "only $rows cases"; exit 1; }
awk -F, 'NR > 1 && !($5 <= $6) { print "out of tolerance: " $0; bad = 1 } END { exit bad }' \
  "$out/validity.csv" || exit 1
echo "validity: $rows cases within tolerance"
