#!/usr/bin/env bash
# `maille run --checkpoint-every N` then `--resume DIR`: 2N steps in one go and N + resume N
# give bit-identical frames, and identical stats.csv rows apart from the timing columns (ns_*).
# Also: a checkpoint interrupted by Ctrl-C resumes; a checkpoint for another scene (the 4th
# argument, by default pendulum_chain.toml beside the scene) is refused.
set -u
maille=$1 scene=$2 out=$3 other=${4:-$(dirname "$2")/pendulum_chain.toml}
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
"$maille" run "$scene" --steps 400 --every 20 --out "$out/whole" >/dev/null || fail "whole run"
"$maille" run "$scene" --steps 200 --every 20 --checkpoint-every 200 --out "$out/split" >/dev/null \
  || fail "first half"
[ -s "$out/split/checkpoint.bin" ] || fail "no checkpoint written"
"$maille" run "$scene" --steps 400 --every 20 --resume "$out/split" >/dev/null || fail "resume"
n_whole=$(ls "$out/whole"/frame_*.ply | wc -l)
n_split=$(ls "$out/split"/frame_*.ply | wc -l)
[ "$n_whole" = "$n_split" ] || fail "frame counts differ: $n_whole vs $n_split"
for f in "$out/whole"/frame_*.ply; do
  cmp -s "$f" "$out/split/$(basename "$f")" || fail "$(basename "$f") differs"
done
# Physics columns: every column whose header does not start with ns_.
physics() {
  awk -F, 'NR==1{for(i=1;i<=NF;i++) keep[i]=($i !~ /^ns_/)} {s=""; for(i=1;i<=NF;i++) if(keep[i]) s=s","$i; print s}' "$1"
}
diff <(physics "$out/whole/stats.csv") <(physics "$out/split/stats.csv") >/dev/null \
  || fail "stats.csv differ"
# A checkpoint cannot be resumed by another scene.
"$maille" run "$other" --steps 10 --resume "$out/split" --out "$out/other" >"$out/other.log" 2>&1
rc=$?
[ $rc -eq 1 ] || fail "resuming another scene's checkpoint: exit $rc, expected 1"
grep -q "another model" "$out/other.log" || fail "no 'another model' in: $(cat "$out/other.log")"
echo "resume bit-identical: $n_whole frames, $(($(wc -l <"$out/whole/stats.csv") - 1)) stats rows"
