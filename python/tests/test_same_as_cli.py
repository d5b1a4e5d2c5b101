"""Runs of a scene from Python and from `maille run` are bit-identical: the state after N steps
(positions, velocities, time, step, the scheme's history, the stages' memory: state_hash) and
the positions of the run's last frame; stats() has stats.csv's columns and last row."""
import csv
import subprocess

import numpy as np
import pytest

import maille
from conftest import CHAIN, DATA, EXAMPLES, FLAG

CASES = [
    (FLAG, 400, ["--threads", "2"], {}, 2),
    (FLAG, 300, ["--set", "flag[0].stiffness=800"], {"flag[0].stiffness": 800.0}, None),
    (CHAIN, 500, ["--set", "simulation.integrator=rk4"], {"simulation.integrator": "rk4"}, None),
    (DATA / "implicit_spring.toml", 200, [], {}, None),
    (EXAMPLES / "shaken_flag.toml", 300, [], {}, None),
    (EXAMPLES / "cloth_heap.toml", 150, [], {}, None),
    (EXAMPLES / "cloth_on_sphere.toml", 150, [], {}, None),
]


def cli_run(exe, scene, steps, args, out):
    subprocess.run([exe, "run", str(scene), "--steps", str(steps), "--checkpoint-every",
                    str(steps), "--out", str(out), "--format", "vtk", *args],
                   check=True, capture_output=True)


@pytest.mark.parametrize("scene,steps,args,overrides,threads", CASES,
                         ids=[f"{c[0].stem}-{c[1]}" for c in CASES])
def test_python_and_maille_run_are_bit_identical(exe, tmp_path, scene, steps, args, overrides,
                                                 threads):
    cli_run(exe, scene, steps, args, tmp_path)
    sim = maille.Simulation(scene, overrides=overrides, threads=threads)
    sim.step(steps)
    cli = maille.Simulation(scene, overrides=overrides, threads=threads)
    cli.load_checkpoint(str(tmp_path / "checkpoint.bin"))
    assert cli.steps == sim.steps == steps
    assert cli.state_hash() == sim.state_hash()
    assert np.array_equal(cli.positions, sim.positions)
    assert np.array_equal(cli.velocities, sim.velocities)


def test_stats_match_stats_csv(exe, tmp_path):
    cli_run(exe, FLAG, 400, [], tmp_path)
    sim = maille.Simulation(FLAG)
    sim.step(400)
    with open(tmp_path / "stats.csv") as f:
        rows = list(csv.reader(f))
    s = sim.stats()
    assert rows[0] == list(s)
    last = dict(zip(rows[0], rows[-1]))
    for key in ("time", "step", "kinetic", "elastic", "gravity", "contact", "total", "wind_faces"):
        # stats.csv prints 6 significant digits
        assert float(last[key]) == pytest.approx(s[key], rel=1e-5, abs=1e-12), key


def test_run_without_arguments_is_maille_run(exe, tmp_path):
    """run() reaches the scene's duration from t = 0, as `maille run` does."""
    overrides = {"simulation.duration": 0.05}
    subprocess.run([exe, "run", str(CHAIN), "--set", "simulation.duration=0.05", "--out",
                    str(tmp_path), "--checkpoint-every", "100000", "--no-frames"],
                   check=True, capture_output=True)
    sim = maille.Simulation(CHAIN, overrides=overrides)
    sim.run()
    cli = maille.Simulation(CHAIN, overrides=overrides)
    cli.load_checkpoint(str(tmp_path / "checkpoint.bin"))
    assert cli.steps == sim.steps == 500
    assert cli.state_hash() == sim.state_hash()
