#!/usr/bin/env bash
# Self-collision contacts beyond the memory budget: exit 1 with a message naming the radius,
# never std::bad_alloc and SIGABRT, under a 3 GB address-space limit. The fourth
# argument is the words the message must hold (default: the particle pairs').
set -u
maille=$1 scene=$2 out=$3 words=${4:-contact pairs}
rm -rf "$out"
# AddressSanitizer reserves terabytes of address space: no limit can be set under it.
if ldd "$maille" 2>/dev/null | grep -q libasan; then echo "skipped: an ASan build"; exit 77; fi
(ulimit -v 3000000; exec "$maille" run "$scene" --steps 3 --no-frames --out "$out") >"$out.log" 2>&1
rc=$?
cat "$out.log"
[ $rc -eq 1 ] || { echo "FAIL: exit $rc, expected 1"; exit 1; }
grep -q "$words" "$out.log" || { echo "FAIL: no message on the contacts ('$words')"; exit 1; }
grep -q "radius 100 m" "$out.log" || { echo "FAIL: the radius is not named"; exit 1; }
echo "refused cleanly"
