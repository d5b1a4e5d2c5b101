"""save_checkpoint / load_checkpoint: a round trip continues bit-identically."""
import numpy as np
import pytest

import maille
from conftest import CHAIN, EXAMPLES, FLAG


@pytest.mark.parametrize("scene,integrator", [(FLAG, None), (CHAIN, "rk4"),
                                              (CHAIN, "implicit_euler"),
                                              (EXAMPLES / "cloth_heap.toml", None)])
def test_round_trip_is_bit_identical(tmp_path, scene, integrator):
    path = str(tmp_path / "c.bin")
    a = maille.Simulation(scene, integrator=integrator, threads=1)
    a.step(60)
    a.save_checkpoint(path)
    saved = (a.positions.copy(), a.velocities.copy(), a.time, a.steps, a.state_hash())
    a.step(60)
    # into the same simulation
    a_end = a.state_hash()
    a.load_checkpoint(path)
    assert np.array_equal(a.positions, saved[0]) and np.array_equal(a.velocities, saved[1])
    assert (a.time, a.steps, a.state_hash()) == saved[2:]
    a.step(60)
    assert a.state_hash() == a_end
    # into a fresh one
    b = maille.Simulation(scene, integrator=integrator, threads=1)
    b.load_checkpoint(path)
    b.step(60)
    assert b.state_hash() == a_end
    assert np.array_equal(b.positions, a.positions)


def test_stats_rows_continue(tmp_path):
    a = maille.Simulation(FLAG)
    a.step(300)
    a.save_checkpoint(str(tmp_path / "c.bin"))
    b = maille.Simulation(FLAG)
    b.load_checkpoint(str(tmp_path / "c.bin"))
    b.step(1)
    a.step(1)
    assert b.time == a.time


def test_corrupt_edited_and_restepped_checkpoints_are_refused(tmp_path):
    """A checksum closes the file; the fingerprint covers every key that changes a trajectory
    (the wind's density here); another step is shown to 17 digits."""
    path = tmp_path / "c.bin"
    a = maille.Simulation(FLAG, threads=1)
    a.step(10)
    a.save_checkpoint(str(path))
    data = bytearray(path.read_bytes())
    data[55] ^= 0xFF  # the frame counter's top byte
    bad = tmp_path / "bad.bin"
    bad.write_bytes(bytes(data))
    with pytest.raises(maille.CheckpointError, match="corrupt"):
        a.load_checkpoint(str(bad))
    windier = maille.Simulation(FLAG, {"fields.wind.density": 1.3}, threads=1)
    with pytest.raises(maille.CheckpointError, match="another model"):
        windier.load_checkpoint(str(path))
    finer = maille.Simulation(FLAG, threads=1, step=0.00025000000000000006)
    with pytest.raises(maille.CheckpointError,
                       match=r"h = 0\.00025000000000000001 s.*h = 0\.00025000000000000006 s"):
        finer.load_checkpoint(str(path))
