"""maille.Simulation: construction, stepping, run() and its callback, the queries."""
import math

import numpy as np
import pytest

import maille
from conftest import CHAIN, FLAG


def test_scene_with_overrides_and_threads():
    sim = maille.Simulation(str(FLAG), overrides={"flag[0].stiffness": 800.0}, threads=2)
    assert sim.point_count == 602
    assert sim.step_size == 2.5e-4
    assert sim.threads == 2
    assert sim.time == 0 and sim.steps == 0
    assert sim.name == "flag_in_wind"
    assert sim.integrator == "leapfrog"
    # overrides as --set strings, and a pathlib.Path
    other = maille.Simulation(FLAG, overrides=["simulation.step=1e-4"])
    assert other.step_size == 1e-4


def test_keyword_settings_are_scene_keys():
    sim = maille.Simulation(CHAIN, step=5e-5, integrator="rk4")
    assert sim.step_size == 5e-5 and sim.integrator == "rk4"


def test_step_advances_time():
    sim = maille.Simulation(CHAIN)
    assert sim.step(100) == 100
    assert sim.steps == 100
    assert sim.time == pytest.approx(100 * 1e-4, rel=1e-12)
    sim.step()
    assert sim.steps == 101


def test_run_duration_every_callback():
    sim = maille.Simulation(CHAIN)
    seen = []
    done = sim.run(duration=0.05, every=10, callback=lambda s: seen.append((s.steps, s.time)))
    assert done == 500
    assert [n for n, _ in seen] == list(range(10, 501, 10))
    # a callback returning False stops the run
    stopped = sim.run(duration=1.0, every=7, callback=lambda s: s.steps < 521)
    assert stopped == 21 and sim.steps == 521
    assert sim.run(steps=20, every=5, callback=lambda s: np.False_) == 5  # falsy stops too


def test_run_without_arguments_reaches_the_scenes_duration():
    sim = maille.Simulation(CHAIN, overrides={"simulation.duration": 0.02})
    sim.step(50)
    assert sim.run() == 150  # to t = 0.02 s from t = 0, as `maille run`
    assert sim.steps == 200
    assert sim.duration == 0.02
    assert sim.run(steps=3) == 3


def test_groups_are_index_arrays():
    sim = maille.Simulation(FLAG)
    g = sim.groups
    assert set(g) == {"flag", "pole"}
    assert g["flag"].dtype == np.int64
    assert np.array_equal(g["flag"], np.arange(0, 600))
    assert np.array_equal(g["pole"], np.array([600, 601]))
    assert sim.fixed[g["pole"]].all()
    assert sim.masses[g["flag"]].sum() == pytest.approx(0.3)


def test_energies():
    sim = maille.Simulation(CHAIN)
    e0 = sim.energies()
    assert set(e0) == {"kinetic", "elastic", "gravity", "contact", "total"}
    assert e0["kinetic"] == 0
    assert e0["total"] == pytest.approx(e0["kinetic"] + e0["elastic"] + e0["gravity"])
    sim.step(2000)
    e = sim.energies()
    assert e["kinetic"] > 0.1  # the chain falls
    # leapfrog with light damping: the total is nearly conserved
    assert e["total"] == pytest.approx(e0["total"], abs=0.02 * abs(e0["gravity"]) + 0.05)


@pytest.mark.parametrize("scene", ["flag_in_wind", "hanging_net", "cloth_heap",
                                   "tablecloth_on_table"])
def test_energies_do_not_change_the_trajectory(scene):
    """Wind, conditional contacts, self-collision, facets (a response stage)."""
    path = FLAG.parent / f"{scene}.toml"
    a = maille.Simulation(path)
    b = maille.Simulation(path)
    for _ in range(5):
        a.step(37)
        a.energies()
        b.step(37)
    assert a.state_hash() == b.state_hash()


def test_stats_has_the_columns_of_stats_csv():
    sim = maille.Simulation(FLAG)
    assert sim.stats() == {}
    sim.step(300)
    s = sim.stats()
    assert list(s)[:7] == ["time", "step", "kinetic", "elastic", "gravity", "contact", "total"]
    assert "ns_link_forces" in s and "wind_faces" in s
    assert s["step"] == 266  # samples every output_every = 133 steps: 0, 133, 266
    assert isinstance(s["step"], int)
    assert s["time"] == pytest.approx(266 * 2.5e-4)


def test_velocity_time_follows_the_scheme():
    sim = maille.Simulation(CHAIN)
    assert sim.velocity_time == "synchronous"
    sim.step()
    assert sim.velocity_time == "half_step"  # leapfrog's v(t - h/2)
    assert maille.Simulation(CHAIN, integrator="rk4").velocity_time == "synchronous"


def test_stable_step_and_counts():
    sim = maille.Simulation(CHAIN)
    assert 0 < sim.step_size < sim.stable_step
    assert sim.link_count > 0
    assert "pendulum_chain" in repr(sim)


def test_reset_goes_back_to_the_start():
    sim = maille.Simulation(CHAIN)
    h0 = sim.state_hash()
    x0 = sim.positions.copy()
    sim.step(300)
    sim.reset()
    assert sim.time == 0 and sim.steps == 0 and sim.stats() == {}
    assert np.array_equal(sim.positions, x0)
    assert sim.state_hash() == h0
    assert not math.isnan(sim.energies()["total"])
