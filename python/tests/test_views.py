"""positions and velocities: zero-copy views of the engine's arrays, writable, kept valid."""
import gc

import numpy as np
import pytest

import maille
from conftest import CHAIN, FLAG


def test_views_are_the_engines_memory():
    sim = maille.Simulation(FLAG)
    x, v = sim.positions, sim.velocities
    assert x.shape == (sim.point_count, 3) and v.shape == (sim.point_count, 3)
    assert x.dtype == v.dtype == np.dtype(maille.real)  # float64 unless MAILLE_SINGLE_PRECISION
    assert not x.flags["OWNDATA"] and x.flags["WRITEABLE"] and x.flags["C_CONTIGUOUS"]
    # two accesses, one memory
    assert np.shares_memory(x, sim.positions)
    assert x.__array_interface__["data"][0] == sim.positions.__array_interface__["data"][0]
    assert not np.shares_memory(x, v)
    before = x.copy()
    sim.step(50)
    assert not np.array_equal(x, before)  # the old view sees the new positions: no copy


def test_writing_a_free_points_row_moves_it():
    sim = maille.Simulation(CHAIN)
    ref = maille.Simulation(CHAIN)
    x = sim.positions
    free = np.nonzero(~sim.fixed)[0][-1]  # the chain's last bead
    x[free] += [0.0, 0.0, 0.01]  # 1 cm out of the chain's plane
    assert sim.positions[free, 2] == 0.01
    sim.step()
    ref.step()
    # it moves on from where it was put (pulled back a little by its link), the rest follows
    assert 0.009 < sim.positions[free, 2] < 0.01
    assert ref.positions[free, 2] == 0
    assert sim.state_hash() != ref.state_hash()


def test_writing_a_velocity_row_is_used_by_the_next_step():
    m = maille.Model()
    i = m.add_point([0, 0, 0], mass=1.0)
    m.set("fields.gravity", [0, 0, 0])
    sim = maille.Simulation(m, step=1e-3)
    sim.velocities[i] = [1.0, 0.0, 0.0]
    sim.step(10)
    assert sim.positions[i, 0] == pytest.approx(0.01, rel=1e-12)


def test_views_keep_the_simulation_alive():
    x = maille.Simulation(CHAIN).positions
    gc.collect()
    assert x.base is not None
    assert np.isfinite(x).all() and x.shape == (13, 3)
    x[1, 0] = 7.0  # still the simulation's memory, which lives as long as the view
    assert x[1, 0] == 7.0


def test_views_stay_valid_across_reset_checkpoint_and_set(tmp_path):
    sim = maille.Simulation(FLAG)
    x = sim.positions
    address = x.__array_interface__["data"][0]
    sim.step(20)
    sim.save_checkpoint(str(tmp_path / "c.bin"))
    sim.step(20)
    sim.load_checkpoint(str(tmp_path / "c.bin"))
    assert sim.positions.__array_interface__["data"][0] == address
    assert np.array_equal(x, sim.positions)
    sim.set("flag[0].stiffness", 500.0)
    sim.reset()
    assert sim.positions.__array_interface__["data"][0] == address
    assert np.array_equal(x, sim.positions)


def test_a_live_edit_that_would_resize_the_state_is_refused():
    sim = maille.Simulation(FLAG)
    with pytest.raises(maille.SceneError) as e:
        sim.set("flag[0].resolution", [10, 10])
    assert e.value.key == "flag[0].resolution"
    assert "number of points" in str(e.value)


def test_views_on_a_device_backend():
    """With the GPU backend (Mesa's software driver when there is no GPU), the views show the
    host copy, brought up to date whenever control returns to Python, and what Python writes
    reaches the device before the next step."""
    try:
        sim = maille.Simulation(CHAIN, overrides={"simulation.backend": "gpu"})
    except (maille.SceneError, RuntimeError) as e:
        pytest.skip(f"no GPU backend here: {e}")
    cpu = maille.Simulation(CHAIN)
    x = sim.positions
    sim.step(200)
    cpu.step(200)
    assert np.shares_memory(x, sim.positions)
    assert np.abs(x - cpu.positions).max() < 1e-5  # float on the device, double on the CPU
    x[-1, 2] += 0.01
    cpu.positions[-1, 2] += 0.01
    sim.step()
    cpu.step()
    assert sim.positions[-1, 2] == pytest.approx(cpu.positions[-1, 2], abs=1e-6)
    assert sim.positions[-1, 2] > 0.009
