#!/usr/bin/env bash
# `maille validate` on every file in examples/ (scenes and sweep files) exits 0; a broken sweep
# file is refused at its line and column (a key the scene does not have, a value it refuses).
set -u
maille=$1 examples=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
count=0
while IFS= read -r -d '' file; do
  "$maille" validate "$file" >"$work/out.log" 2>&1 || { cat "$work/out.log"; fail "$file"; }
  count=$((count + 1))
done < <(find "$examples" -name '*.toml' -print0 | sort -z)
"$maille" validate "$examples/sweeps/flag_stiffness.toml" | grep -q ": ok (a sweep of" ||
  fail "the sweep file is not validated as one"

cp "$examples/flag_in_wind.toml" "$work/scene.toml"
printf 'scene = "scene.toml"\nduration = 0.1\n[axes]\n"flag[0].stiffnes" = [100.0, 200.0]\n' >"$work/bad_key.toml"
"$maille" validate "$work/bad_key.toml" >"$work/out.log" 2>&1
[ $? -eq 1 ] || fail "a bad axis key was accepted"
grep -q "bad_key.toml:4:1: error: key 'axes.\"flag\[0\].stiffnes\"'" "$work/out.log" ||
  { cat "$work/out.log"; fail "the bad key is not located"; }
printf 'scene = "scene.toml"\n[axes]\n"flag[0].stiffness" = [100.0,\n  -5.0]\n' >"$work/bad_value.toml"
"$maille" validate "$work/bad_value.toml" >"$work/out.log" 2>&1
[ $? -eq 1 ] || fail "a bad axis value was accepted"
grep -Eq 'bad_value.toml:3:1: .*value -5(\.0)? \(value 2 of 2\)' "$work/out.log" ||
  { cat "$work/out.log"; fail "the bad value is not located"; }
printf 'scene = "scene.toml"\n[axes]\n"flag[0].stiffness" = [100.0\n' >"$work/bad_syntax.toml"
"$maille" validate "$work/bad_syntax.toml" >"$work/out.log" 2>&1
[ $? -eq 1 ] || fail "a sweep file with a syntax error was accepted"
echo "validated $count example files"
