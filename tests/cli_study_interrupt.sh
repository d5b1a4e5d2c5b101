#!/usr/bin/env bash
# Ctrl-C (SIGINT) and SIGTERM stop `maille study` and scripts/report.sh with exit 130, leaving
# no *.tmp and no half-made data folder; report.sh keeps the previous data (zero-byte
# crossover.csv.tmp and incline.csv.tmp used to stay behind).
# Usage: cli_study_interrupt.sh MAILLE OUT SOURCE_DIR
set -u
maille=$1 out=$2 src=$3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$out"; mkdir -p "$out"
for sig in INT TERM; do
  "$maille" study all --quick --out "$out/study_$sig" >"$out/study_$sig.log" 2>&1 &
  pid=$!
  sleep 2
  kill -$sig $pid
  wait $pid
  rc=$?
  [ $rc -eq 130 ] || fail "study, SIG$sig: exit $rc, expected 130: $(cat "$out/study_$sig.log")"
  grep -q "interrupted" "$out/study_$sig.log" || fail "study, SIG$sig: no message"
  left=$(find "$out/study_$sig" -name '*.tmp')
  [ -z "$left" ] || fail "study, SIG$sig: temporaries left: $left"
done

# scripts/report.sh on this build (MAILLE_NO_BUILD: nothing rebuilt), when the build is
# build/PRESET of the source and matplotlib is there (report.sh would install it).
preset=$(basename "$(dirname "$(dirname "$(dirname "$maille")")")")
if [ "$(cd "$(dirname "$maille")/../../.." && pwd)" != "$(cd "$src/build" && pwd)" ] ||
  ! /usr/bin/python3 -c 'import matplotlib' 2>/dev/null; then
  echo "study interrupted cleanly; report.sh not tried (build outside $src/build or no matplotlib)"
  exit 0
fi
mkdir -p "$out/report/data"
echo kept >"$out/report/data/previous"
MAILLE_PRESET=$preset MAILLE_NO_BUILD=1 MAILLE_NO_GALLERY=1 \
  "$src/scripts/report.sh" --quick --out "$out/report" >"$out/report.log" 2>&1 &
pid=$!
sleep 3
kill -TERM $pid
wait $pid
rc=$?
[ $rc -eq 130 ] || fail "report.sh: exit $rc, expected 130: $(tail -5 "$out/report.log")"
[ -d "$out/report/data.new" ] && fail "report.sh left data.new"
[ "$(cat "$out/report/data/previous" 2>/dev/null)" = kept ] || fail "report.sh lost the previous data"
left=$(find "$out/report" -name '*.tmp')
[ -z "$left" ] || fail "report.sh: temporaries left: $left"
sleep 0.5
pgrep -f "study all --quick --out $out/report/data.new" >/dev/null && fail "the study still runs"
echo "study and report.sh interrupted cleanly (exit 130, no *.tmp, previous data kept)"
