#!/usr/bin/env python3
"""A cloth driven from a Python callback: the flag of examples/flag_in_wind.toml whose pole
points (fixed) are moved up and down by the callback, writing their rows of the positions and
velocities views, while the wind is turned by a live edit halfway. Writes the height of the
free corner over time (corner.csv) and, when rendering is built, a still (cloth.png).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/cloth_callback.py --out out/cloth
"""
import argparse
import csv
import math
import pathlib
import sys

import numpy as np

import maille

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/cloth_callback")
    ap.add_argument("--quick", action="store_true", help="0.2 s, a small still (tests)")
    ap.add_argument("--duration", type=float, default=3.0)
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    duration = 0.2 if a.quick else a.duration

    sim = maille.Simulation(ROOT / "examples/flag_in_wind.toml")
    x, v = sim.positions, sim.velocities  # views: what the callback writes, the engine reads
    flag = sim.groups["flag"]
    pole = flag[sim.fixed[flag]]  # the flag's fixed points: its edge on the pole
    rest = x[pole].copy()
    corner = flag[-1]
    amplitude, frequency = 0.15, 1.5  # m, Hz
    omega = 2 * math.pi * frequency
    trace = []
    turned = False

    def drive(s):
        nonlocal turned
        t = s.time
        # The pole's points follow y0 + A sin(wt); their velocity is the path's (dampers read it).
        x[pole, 1] = rest[:, 1] + amplitude * math.sin(omega * t)
        v[pole, 1] = amplitude * omega * math.cos(omega * t)
        if not turned and t >= duration / 2:
            s.set("fields.wind.velocity", [0.0, 0.0, 7.0])  # the wind turns by 90 degrees
            turned = True
        trace.append((t, x[corner, 1], s.energies()["total"]))

    sim.run(duration=duration, every=10, callback=drive)
    with open(out / "corner.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "corner_height", "total_energy"])
        w.writerows(trace)
    heights = np.array([r[1] for r in trace])
    print(f"{sim.steps} steps to t = {sim.time:.3f} s; free corner height from {heights.min():.3f} "
          f"to {heights.max():.3f} m; wrote {out / 'corner.csv'}")
    if maille.render_available:
        size = (320, 180) if a.quick else (960, 540)
        sim.render(str(out / "cloth.png"), width=size[0], height=size[1])
        print(f"wrote {out / 'cloth.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
