#!/usr/bin/env bash
# A full disk: `maille run` whose stats.csv (or first frame) lands on /dev/full must exit 4 with
# the cause ("No space left on device"), leave no temporary file and keep what was there before.
set -u
maille=$1 scene=$2 out=$3 victim=$4  # victim: stats.csv or frame_000000.ply
rm -rf "$out"
mkdir -p "$out"
echo "previous" >"$out/$victim"
ln -s /dev/full "$out/$victim.tmp"  # the temporary is opened through the link: writes fail
timeout 60 "$maille" run "$scene" --steps 20 --out "$out" >"$out.log" 2>&1
rc=$?
cat "$out.log"
[ $rc -eq 4 ] || { echo "exit code $rc, expected 4"; exit 1; }
grep -q "No space left on device" "$out.log" || { echo "the cause is not named"; exit 1; }
[ "$(cat "$out/$victim")" = "previous" ] || { echo "$victim was overwritten"; exit 1; }
ls "$out"/*.tmp >/dev/null 2>&1 && { echo "temporary files left"; exit 1; }
echo "full disk reported, nothing half-written"
