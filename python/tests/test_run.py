"""maille.run(): a scene file run as `maille run` runs it (the same SceneRun): its files, its
summary, and each way it can end as the exception of its exit code, after the files are
closed. (cli.scene_run_same_stats compares its stats.csv with maille run's and a sweep's.)"""
import csv

import pytest

import maille
from conftest import CHAIN, UNSTABLE


def test_run_writes_the_files_and_returns_the_summary(tmp_path):
    r = maille.run(CHAIN, {"rope[0].stiffness": 3000.0}, out=tmp_path / "chain", steps=300,
                   threads=1, every=100, checkpoint_every=300)
    assert r["name"] == "pendulum_chain" and r["out"] == str(tmp_path / "chain")
    assert r["steps"] == 300 and r["frames"] == 4 and r["stats_rows"] == 3
    assert set(r["energies"]) == {"kinetic", "elastic", "gravity", "contact", "total"}
    rows = list(csv.reader(open(tmp_path / "chain" / "stats.csv")))
    assert len(rows) == 4 and rows[0][:2] == ["time", "step"]
    assert (tmp_path / "chain" / "frame_000003.ply").exists()
    # The checkpoint is the command line's: a Simulation continues from it.
    sim = maille.Simulation(CHAIN, {"rope[0].stiffness": 3000.0})
    sim.load_checkpoint(tmp_path / "chain" / "checkpoint.bin")
    assert sim.steps == 300


def test_without_steps_it_runs_the_scene_duration(tmp_path):
    r = maille.run(CHAIN, {"simulation.duration": 0.02}, out=tmp_path, frames=False)
    assert r["steps"] == 200 and r["frames"] == 0


def test_a_bad_override_is_a_scene_error_and_writes_nothing(tmp_path):
    with pytest.raises(maille.SceneError) as e:
        maille.run(CHAIN, {"rope[0].stiffness": -1.0}, out=tmp_path / "none", steps=10)
    assert e.value.key == "rope[0].stiffness"
    assert not (tmp_path / "none").exists()


@pytest.mark.parametrize("kwargs,key", [({"format": "png"}, "format"), ({"steps": -1}, "steps"),
                                        ({"duration": float("nan")}, "duration"),
                                        ({"threads": 0}, "threads"), ({"every": 0}, "every")])
def test_bad_arguments_name_themselves(tmp_path, kwargs, key):
    with pytest.raises(maille.SceneError) as e:
        maille.run(CHAIN, out=tmp_path, **kwargs)
    assert e.value.key == key


def test_a_blow_up_raises_with_the_files_complete(tmp_path):
    with pytest.raises(maille.BlowUp) as e, pytest.warns(UserWarning, match="stability estimate"):
        maille.run(UNSTABLE, out=tmp_path, steps=2000, frames=False)
    assert e.value.step > 0
    assert (tmp_path / "stats.csv").exists()


def test_an_output_that_cannot_be_made_is_an_os_error(tmp_path):
    (tmp_path / "file").write_text("not a folder")
    with pytest.raises(OSError) as e:
        maille.run(CHAIN, out=tmp_path / "file" / "run", steps=10)
    assert "cannot create the output directory" in str(e.value)
