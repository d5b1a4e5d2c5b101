#!/usr/bin/env python3
"""A parameter scan from Python: the flag of examples/flag_in_wind.toml at several structural
stiffnesses, each run for the same simulated time; the flag's mean kinetic energy and the
mean height of its free corner against the stiffness, plotted with matplotlib (Agg) to a PNG.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/parameter_scan.py --out out/scan
"""
import argparse
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import maille

ROOT = pathlib.Path(__file__).resolve().parents[2]


def scan(stiffnesses, duration, threads):
    rows = []
    for k in stiffnesses:
        sim = maille.Simulation(ROOT / "examples/flag_in_wind.toml",
                                overrides={"flag[0].stiffness": k}, threads=threads)
        flag = sim.groups["flag"]
        corner = flag[-1]  # (nx - 1, ny - 1): the free top corner
        kinetic, height = [], []

        def sample(s):
            kinetic.append(s.energies()["kinetic"])
            height.append(s.positions[corner, 1])

        sim.run(duration=duration, every=max(1, int(round(0.01 / sim.step_size))), callback=sample)
        rows.append((k, float(np.mean(kinetic)), float(np.mean(height))))
        print(f"stiffness {k:8.1f} N/m: mean kinetic energy {rows[-1][1]:.4g} J, "
              f"mean corner height {rows[-1][2]:.4f} m")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/parameter_scan", help="directory for scan.csv, scan.png")
    ap.add_argument("--quick", action="store_true", help="3 stiffnesses, 0.1 s each (tests)")
    ap.add_argument("--threads", type=int, default=1)
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    if a.quick:
        stiffnesses, duration = [100.0, 300.0, 900.0], 0.1
    else:
        stiffnesses, duration = list(np.geomspace(50.0, 1600.0, 6)), 2.0
    rows = scan(stiffnesses, duration, a.threads)
    with open(out / "scan.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stiffness", "mean_kinetic", "mean_corner_height"])
        w.writerows(rows)
    k, e, h = np.array(rows).T
    fig, ax = plt.subplots(1, 2, figsize=(9, 3.5))
    ax[0].semilogx(k, e, "o-")
    ax[0].set_xlabel("structural stiffness (N/m)")
    ax[0].set_ylabel("mean kinetic energy (J)")
    ax[1].semilogx(k, h, "o-")
    ax[1].set_xlabel("structural stiffness (N/m)")
    ax[1].set_ylabel("mean height of the free corner (m)")
    fig.suptitle(f"flag_in_wind, {duration:g} s simulated per stiffness")
    fig.tight_layout()
    fig.savefig(out / "scan.png", dpi=100)
    print(f"wrote {out / 'scan.csv'} and {out / 'scan.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
