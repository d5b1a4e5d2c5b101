"""maille.Model: points, links of any registered kind, builders, fields; and the physics of a
model built in code."""
import math

import numpy as np
import pytest

import maille
from conftest import FLAG


def test_points_and_links():
    m = maille.Model()
    i = m.add_point([0, 1, 0], mass=0.01)
    j = m.add_fixed_point([0, 2, 0])
    assert (i, j) == (0, 1)
    assert m.add_link("spring_damper", i, j, stiffness=100.0, damping=0.1) == 0
    k = m.add_point([1, 1, 0], velocity=[0, 0, 1], name="bob")
    assert m.add_link("spring", "bob", j, stiffness=10.0) == 0  # ids count per kind
    assert m.add_link("damper", i, k, damping=0.5) == 0
    assert m.add_link("conditional", i, k, stiffness=50.0, threshold=0.2) == 0
    assert m.point_count == 3 and m.link_count == 4
    assert np.array_equal(m.groups["bob"], [2])
    assert np.array_equal(m.positions, [[0, 1, 0], [0, 2, 0], [1, 1, 0]])
    sim = maille.Simulation(m, step=1e-4)
    assert sim.point_count == 3 and sim.link_count == 4
    assert sim.fixed.tolist() == [False, True, False]
    assert np.array_equal(sim.velocities[k], [0, 0, 1])


def test_rest_length_defaults_to_the_distance():
    m = maille.Model()
    i = m.add_point([0, 0.5, 0])
    j = m.add_fixed_point([0, 2, 0])
    m.add_link("spring_damper", i, j, stiffness=100.0)
    m.set("fields.gravity", [0, 0, 0])
    sim = maille.Simulation(m, step=1e-3)
    e = sim.energies()
    assert e["elastic"] == 0  # at rest length: no force, no energy
    sim.step(100)
    assert sim.positions[i, 1] == 0.5


def test_fields_default_as_in_a_scene_file():
    m = maille.Model()
    i = m.add_point([0, 0, 0], mass=2.0)
    sim = maille.Simulation(m, step=1e-3)
    sim.step(1)
    # leapfrog's first step from rest: v(h/2) = g h / 2, x(h) = g h^2 / 2 with g = -9.81
    assert sim.positions[i, 1] == pytest.approx(-9.81 * 1e-6 / 2, rel=1e-12)
    assert sim.energies()["gravity"] == pytest.approx(2.0 * 9.81 * sim.positions[i, 1])


def test_builders_make_what_the_scene_file_makes():
    """flag_in_wind.toml rebuilt in code: the same flag, pole and fields give a bit-identical run."""
    m = maille.Model()
    flag = m.add_flag(name="flag", origin=[0.0, 2.0, 0.0], width=1.5, height=1.0,
                      resolution=[30, 20], mass=0.3, stiffness=300.0, shear_stiffness=100.0,
                      bending_stiffness=10.0, damping=0.02, fixed="pole")
    pole = m.add_rope(name="pole", start=[0, 0, 0], end=[0, 3.1, 0], points=2, mass=1.0,
                      stiffness=1.0, damping=0.0, fixed="both")
    assert np.array_equal(flag, np.arange(600)) and np.array_equal(pole, [600, 601])
    m.set("fields.air_drag", 0.05)
    m.set("fields.wind", {"velocity": [7.0, 0.0, 1.5], "density": 1.2, "drag_coefficient": 1.0,
                          "turbulence": 0.35, "gust_frequency": 0.8, "gust_wavelength": 1.5})
    m.set("simulation.output_every", 133)
    code = maille.Simulation(m, step=2.5e-4, threads=1)
    scene = maille.Simulation(FLAG, threads=1)
    assert np.array_equal(code.positions, scene.positions)
    code.step(400)
    scene.step(400)
    assert code.state_hash() == scene.state_hash()
    assert code.stats()["wind_faces"] == scene.stats()["wind_faces"] == 1102


def test_every_builder():
    m = maille.Model()
    sizes = {
        "rope": m.add_rope(points=5).size,
        "net": m.add_net(resolution=[4, 3], origin=[0, 3, 0]).size,
        "membrane": m.add_membrane(rings=3, center=[3, 0, 0]).size,
        "lattice": m.add_lattice(resolution=[2, 2, 3], origin=[5, 0, 0]).size,
        "floor": m.add_floor(resolution=[3, 3], center=[0, -1, 0]).size,
        "flag": m.build("flag", resolution=[3, 2], origin=[0, 5, 0]).size,
    }
    assert sizes["rope"] == 5 and sizes["net"] == 12 and sizes["lattice"] == 12
    assert sizes["floor"] == 9 and sizes["flag"] == 6
    assert m.point_count == sum(sizes.values())
    assert list(m.groups) == ["rope0", "net1", "membrane2", "lattice3", "floor4", "flag5"]
    sim = maille.Simulation(m, step=1e-4)
    sim.step(10)
    assert np.isfinite(sim.positions).all()


def period_of(t, y):
    y = y - y.mean()
    up = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    crossings = t[up] - y[up] * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    return float(np.mean(np.diff(crossings)))


def oscillate(mass, k, damping, h, periods):
    m = maille.Model()
    i = m.add_point([0, 1, 0], mass=mass)
    j = m.add_fixed_point([0, 2, 0])
    m.add_link("spring_damper", i, j, stiffness=k, damping=damping)
    sim = maille.Simulation(m, step=h)
    y = sim.positions[:, 1]
    n = int(round(periods * 2 * math.pi * math.sqrt(mass / k) / h))
    t, z = np.empty(n), np.empty(n)
    for s in range(n):
        sim.step()
        t[s], z[s] = sim.time, y[i]
    return t, z


def test_mass_on_a_spring_oscillates_with_the_analytic_period():
    """m = 0.01 kg on k = 100 N/m: T = 2 pi sqrt(m/k) = 62.83 ms. Leapfrog at h = 1e-4 s
    (omega h = 0.01) shortens the period by (omega h)^2 / 24 = 4.2e-6 relative (measured:
    -4.17e-6); crossings are interpolated linearly between steps, averaged over 20 periods.
    Tolerance 2e-5: five times the scheme's own error, and 25 times finer than the shift a
    0.1 % error in k would give (5e-4)."""
    mass, k, h = 0.01, 100.0, 1e-4
    t, y = oscillate(mass, k, 0.0, h, 20)
    expected = 2 * math.pi * math.sqrt(mass / k)
    assert period_of(t, y) == pytest.approx(expected, rel=2e-5)
    # gravity only moves the centre: m g / k = 0.98 mm below the rest point
    assert y.mean() == pytest.approx(1 - mass * 9.81 / k, abs=2e-5)


def test_damped_period_and_decay():
    """With damping c = 0.1 N.s/m, zeta = c / (2 sqrt(k m)) = 0.05: the period is
    T / sqrt(1 - zeta^2) (0.125 % longer than undamped, which the tolerance separates) and the
    amplitude decays as exp(-zeta omega t). Leapfrog's damper reads the staggered velocity
    v(t - h/2): measured 5.4e-5 on the period and 3e-4 on the decay over four periods, hence
    tolerances of 2e-4 and 0.5 %."""
    mass, k, c, h = 0.01, 100.0, 0.1, 1e-4
    t, y = oscillate(mass, k, c, h, 6)
    zeta = c / (2 * math.sqrt(k * mass))
    omega = math.sqrt(k / mass)
    expected = 2 * math.pi / (omega * math.sqrt(1 - zeta**2))
    centre = 1 - mass * 9.81 / k
    measured = period_of(t, y - centre + y.mean())
    assert measured == pytest.approx(expected, rel=2e-4)
    assert abs(measured / (2 * math.pi / omega) - 1) > 1e-3
    # peaks of the first and fifth oscillations
    d = np.abs(y - centre)
    T = 2 * math.pi / omega
    first = d[(t > 0.5 * T) & (t < 1.5 * T)].max()
    fifth = d[(t > 4.5 * T) & (t < 5.5 * T)].max()
    assert fifth / first == pytest.approx(math.exp(-zeta * omega * 4 * expected), rel=0.005)
