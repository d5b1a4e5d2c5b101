#!/usr/bin/env bash
# cli_sweep_bad.sh MAILLE SCENE OUT: bad sweep files are refused with file:line:column and the
# key, exit 1, and nothing is written (no output directory).
set -u
maille=$1 scene=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
n=0
# expect NAME PATTERN: writes $out/NAME.toml from stdin, runs it, checks the refusal.
expect() {
  local name=$1 pattern=$2 file=$out/$1.toml
  cat >"$file"
  local log rc
  log=$(timeout 60 "$maille" sweep "$file" --out "$out/$name.out" 2>&1)
  rc=$?
  printf '%s\n' "$log"
  [ $rc -eq 1 ] || { echo "FAIL: $name: exit code $rc, expected 1"; exit 1; }
  grep -qE -- "$pattern" <<<"$log" || { echo "FAIL: $name: no /$pattern/"; exit 1; }
  [ -e "$out/$name.out" ] && { echo "FAIL: $name: $out/$name.out was created"; exit 1; }
  n=$((n + 1))
}

expect unknown_key "unknown_key.toml:4:1: error: key 'axes.\"rope\[0\]\.stifness\"': not a key of the scene .*unknown key" <<EOF
scene = "$scene"
duration = 0.1
[axes]
"rope[0].stifness" = [1.0, 2.0]
EOF
expect index_out_of_range "index_out_of_range.toml:4:1: error: key 'axes.\"rope\[3\]\.stiffness\"'.*index out of range" <<EOF
scene = "$scene"
[axes]
"rope[0].damping" = [0.1]
"rope[3].stiffness" = [1.0]
EOF
expect no_such_table "no_such_table.toml:3:1: error: key 'axes.\"ropes\[0\]\.mass\"'.*no \[\[ropes\]\] table" <<EOF
scene = "$scene"
[axes]
"ropes[0].mass" = [1.0]
EOF
expect empty_axis "empty_axis.toml:3:23: error: key 'axes.\"rope\[0\]\.stiffness\"': must be a non-empty array" <<EOF
scene = "$scene"
[axes]
"rope[0].stiffness" = []
EOF
expect axis_not_array "axis_not_array.toml:3:21: error: key 'axes.\"simulation.step\"': must be a non-empty array" <<EOF
scene = "$scene"
[axes]
"simulation.step" = 1e-4
EOF
expect bad_duration "bad_duration.toml:2:12: error: key 'duration': must be a number of seconds" <<EOF
scene = "$scene"
duration = -1.0
[axes]
"simulation.step" = [1e-4]
EOF
expect missing_scene "missing_scene.toml:1:1: error: key 'scene': the scene does not load: .*nowhere.toml" <<EOF
scene = "nowhere.toml"
[axes]
"simulation.step" = [1e-4]
EOF
expect unknown_top_key "unknown_top_key.toml:2:1: error: key 'frames': unknown key" <<EOF
scene = "$scene"
frames = true
[axes]
"simulation.step" = [1e-4]
EOF
expect frames_not_bool "frames_not_bool.toml:5:10: error: key 'output.frames': must be true or false" <<EOF
scene = "$scene"
[axes]
"simulation.step" = [1e-4]
[output]
frames = "yes"
EOF
expect no_axes "no_axes.toml:1:1: error: key 'axes': is required but missing" <<EOF
scene = "$scene"
duration = 1.0
EOF
expect toml_syntax "toml_syntax.toml:2:6: error: TOML syntax" <<EOF
scene = "$scene"
[axes
"simulation.step" = [1e-4]
EOF
expect malformed_key "malformed_key.toml:3:1: error: key 'axes.\"simulation step\"': an axis is named by a scene key path" <<EOF
scene = "$scene"
[axes]
"simulation step" = [1e-4]
EOF
echo "$n bad sweep files refused at their line, nothing written"
