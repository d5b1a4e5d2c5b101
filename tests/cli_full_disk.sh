#!/usr/bin/env bash
# cli_full_disk.sh OUT VICTIM COMMAND [ARGS...]: a full disk. OUT/VICTIM's temporary
# (VICTIM.tmp) is a link to /dev/full; COMMAND (which writes into OUT) must exit 4 naming the
# cause ("No space left on device"), leave no temporary file and keep the VICTIM already there.
set -u
out=$1 victim=$2
shift 2
rm -rf "$out"
mkdir -p "$out"
echo "previous" >"$out/$victim"
ln -s /dev/full "$out/$victim.tmp"  # the temporary is opened through the link: writes fail
timeout 120 "$@" >"$out.log" 2>&1
rc=$?
cat "$out.log"
[ $rc -eq 4 ] || { echo "exit code $rc, expected 4"; exit 1; }
grep -q "No space left on device" "$out.log" || { echo "the cause is not named"; exit 1; }
[ "$(cat "$out/$victim")" = "previous" ] || { echo "$victim was overwritten"; exit 1; }
ls "$out"/*.tmp >/dev/null 2>&1 && { echo "temporary files left"; exit 1; }
echo "full disk reported, nothing half-written"
