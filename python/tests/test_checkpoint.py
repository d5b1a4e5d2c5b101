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
