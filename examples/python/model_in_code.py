#!/usr/bin/env python3
"""A model built in code: a mass on a spring under a fixed point, whose measured period is
compared with 2 pi sqrt(m / k), and a rope of beads hung beside it with the rope builder,
all in one maille.Model. Plots the mass's height over time (oscillator.png).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/model_in_code.py --out out/model
"""
import argparse
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import maille


def period_of(t, y):
    """Mean period from the upward crossings of y through its mean (linear interpolation)."""
    y = y - y.mean()
    up = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    crossings = t[up] - y[up] * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    return float(np.mean(np.diff(crossings)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/model_in_code")
    ap.add_argument("--quick", action="store_true", help="a shorter run (tests)")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)

    m = maille.Model()
    mass, k = 0.01, 100.0  # kg, N/m
    i = m.add_point([0, 1, 0], mass=mass)
    j = m.add_fixed_point([0, 2, 0])
    m.add_link("spring_damper", i, j, stiffness=k, damping=0.0)  # rest length: the distance
    rope = m.add_rope(name="rope", start=[1, 2, 0], end=[2, 2, 0], points=10, mass=0.1,
                      stiffness=500.0, damping=0.01, fixed="start")
    sim = maille.Simulation(m, step=1e-4)
    y = sim.positions[:, 1]  # a view: read in place after every step
    periods = 3 if a.quick else 20
    n = int(round(periods * 2 * math.pi * math.sqrt(mass / k) / sim.step_size))
    t = np.empty(n)
    h = np.empty(n)
    for s in range(n):
        sim.step()
        t[s], h[s] = sim.time, y[i]
    measured = period_of(t, h)
    expected = 2 * math.pi * math.sqrt(mass / k)
    print(f"{m.point_count} points, {m.link_count} links; rope points {rope[0]}..{rope[-1]}")
    print(f"period measured {measured * 1e3:.4f} ms, 2 pi sqrt(m/k) = {expected * 1e3:.4f} ms, "
          f"relative difference {abs(measured / expected - 1):.2e}")
    fig, ax = plt.subplots(figsize=(6, 3))
    ax.plot(t, h)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("height of the mass (m)")
    ax.set_title(f"mass on a spring: period {measured * 1e3:.3f} ms")
    fig.tight_layout()
    fig.savefig(out / "oscillator.png", dpi=100)
    print(f"wrote {out / 'oscillator.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
