#!/usr/bin/env bash
# `maille study obstacles --quick`: the three tables exist with their columns; the facets never
# let the cloth into the exact cube; the incline slides match the analytic distance (1 %).
set -u
maille=$1 out=$2
rm -rf "$out"
"$maille" study obstacles --quick --out "$out" >/dev/null || { echo "study failed"; exit 1; }
for f in obstacles incline lean; do [ -s "$out/$f.csv" ] || { echo "$f.csv missing"; exit 1; }; done
head -1 "$out/obstacles.csv" | grep -q "^shape,method,particles,steps,max_penetration_m,mean_contacts,obstacle_ns_pps,link_ns_pps$" \
  || { echo "bad header: $(head -1 "$out/obstacles.csv")"; exit 1; }
[ "$(($(wc -l <"$out/obstacles.csv") - 1))" -eq 9 ] || { echo "expected 9 shape x method rows"; exit 1; }
awk -F, '$2 == "facets" && ($1 == "cube" || $1 == "rotated_cube") && $5 > 0 { print "facets let the cloth in: " $0; bad = 1 } END { exit bad }' \
  "$out/obstacles.csv" || exit 1
awk -F, 'NR > 1 && $1 != "conditional" && $7 > 0.01 { print "incline off: " $0; bad = 1 } END { exit bad }' \
  "$out/incline.csv" || exit 1
echo "obstacles study: tables complete, facets tight, inclines within 1 %"
