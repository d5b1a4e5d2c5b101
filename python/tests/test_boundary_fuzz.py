"""The Python boundary's fuzz target (fuzz_boundary.py): a few thousand random calls with hostile
values, in subprocesses, so that a crash fails this test with the case that caused it instead of
ending the test run. MAILLE_FUZZ_CASES sets the count (default 3000)."""
import os
import pathlib
import signal
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent

# A small scene with every kind of stage the boundary can reach cheaply: a cloth colliding
# with itself (particle-face contacts) and with a sphere, driven by wind.
SCENE = """
[simulation]
step = 1e-3
duration = 0.05
output_every = 5
[fields]
gravity = [0.0, -9.81, 0.0]
wind = { velocity = [2.0, 0.0, 1.0], turbulence = 0.2 }
[[flag]]
name = "cloth"
origin = [-0.25, 0.5, -0.25]
along = [1.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
width = 0.5
height = 0.5
resolution = [6, 6]
mass = 0.05
stiffness = 50.0
damping = 0.01
fixed = "none"
[[obstacle]]
name = "ball"
shape = "sphere"
method = "geometric"
position = [0.0, 0.2, 0.0]
scale = [0.2, 0.2, 0.2]
collides_with = ["cloth"]
[self_collision]
groups = ["cloth"]
primitive = "triangles"
radius = 0.02
topological_radius = 0
"""


def test_random_hostile_calls_never_crash(tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE)
    cases = int(os.environ.get("MAILLE_FUZZ_CASES", "3000"))
    chunk = 500
    for first in range(0, cases, chunk):
        work = tmp_path / f"chunk{first}"
        work.mkdir()
        proc = subprocess.run(
            [sys.executable, str(HERE / "fuzz_boundary.py"), str(scene), str(work), str(first),
             str(min(chunk, cases - first))],
            capture_output=True, text=True, timeout=600)
        last = (work / "last_seed").read_text().strip() if (work / "last_seed").exists() else "?"
        assert proc.returncode >= 0, (
            f"killed by {signal.Signals(-proc.returncode).name} at {last}\n{proc.stderr[-3000:]}")
        assert proc.returncode == 0, proc.stdout[-5000:] + proc.stderr[-3000:]
        assert "done" in proc.stdout
