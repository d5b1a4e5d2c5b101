#!/usr/bin/env bash
# `pip install .` (pyproject.toml, python/build_backend/maille_build.py): into a fresh virtual
# environment that sees Debian's NumPy (--system-site-packages), offline (--no-index: pip may
# fetch nothing), building the module in this test's CMake build (MAILLE_BUILD_DIR: up to date,
# so nothing is compiled again); then `import maille` from another folder runs a scene and
# gives the state hash of the build's own module.
set -euo pipefail
python=$1 source=$2 build=$3 work=$4
rm -rf "$work"
mkdir -p "$work/elsewhere"
"$python" -m venv --system-site-packages "$work/venv"
MAILLE_BUILD_DIR=$build "$work/venv/bin/pip" install --no-index --no-cache-dir --quiet "$source"
cd "$work/elsewhere"
installed=$(PYTHONPATH= "$work/venv/bin/python" -c "
import maille, sys
assert '$work/venv/' in maille.__file__, maille.__file__
sim = maille.Simulation('$source/examples/pendulum_chain.toml')
sim.step(200)
print(sim.state_hash())")
built=$(PYTHONPATH=$build/python "$python" -c "
import maille
sim = maille.Simulation('$source/examples/pendulum_chain.toml')
sim.step(200)
print(sim.state_hash())")
echo "installed module: state hash $installed after 200 steps; the build's: $built"
[ "$installed" = "$built" ] || { echo "FAIL: the installed module differs from the build's"; exit 1; }
echo "pip install . works offline; import maille from another folder runs a scene"
