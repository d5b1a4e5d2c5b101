#!/usr/bin/python3
"""Draws the study's figures and fills docs/report.md from the measured CSV files.

    report.py --data DIR --figures DIR [--template FILE --md FILE]

DIR (the output of `maille study all`, written by scripts/report.sh):
    validity/validity.csv
    integrators/{stability,accuracy,energy,cost,crossover}.csv
    self-collision/{scaling,cell_size,tuner,exclusion,memory,flag_wind}.csv
    obstacles/{obstacles,incline,lean}.csv
    large-steps/large_steps.csv
    durations.csv   wall time of each study (maille study all)
    run.csv         key,value: how and where the data was made (scripts/report.sh)
    peer.csv        optional: bench/peer_bullet's comparison with Bullet's soft bodies

Every figure in FIGURES is written as PNG (peer.png only when peer.csv exists). With --template,
every {{key}} in the template is replaced by a value computed here from the CSV files; a key
this script does not know is an error, so no number in the report is typed by hand.
Needs only matplotlib and numpy (Debian's python3-matplotlib).
"""
import argparse
import csv
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FIGURES = [
    "validity.png",
    "stability.png",
    "accuracy.png",
    "energy.png",
    "cost.png",
    "crossover.png",
    "self_collision_scaling.png",
    "self_collision_cell_size.png",
    "self_collision_memory.png",
    "obstacles.png",
    "incline.png",
    "large_steps.png",
]
OPTIONAL_FIGURES = ["peer.png"]  # drawn when peer.csv exists

SCHEMES = ["explicit_euler", "symplectic_euler", "leapfrog", "velocity_verlet", "rk4",
           "implicit_euler"]
THEORY_ORDER = {"explicit_euler": 1, "symplectic_euler": 1, "leapfrog": 2,
                "velocity_verlet": 2, "rk4": 4, "implicit_euler": 1}
COLOURS = {"explicit_euler": "tab:red", "symplectic_euler": "tab:orange", "leapfrog": "tab:blue",
           "velocity_verlet": "tab:cyan", "rk4": "tab:purple", "implicit_euler": "tab:green",
           "brute": "tab:red", "uniform": "tab:blue", "hashed": "tab:orange",
           "hierarchical": "tab:green", "geometric": "tab:blue", "facets": "tab:orange",
           "conditional": "tab:green"}
DPI = 80


# --- reading -------------------------------------------------------------------------------

def read(path):
    """Rows of a CSV file as dicts, numbers converted (empty fields are None)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k, v in r.items():
            if k in ("version", "commit"):  # "3.10" is not 3.1
                continue
            if v is None or v == "":
                r[k] = None
                continue
            try:
                r[k] = float(v)
            except ValueError:
                r[k] = v
    return rows


class Data:
    def __init__(self, root):
        self.root = root

    def __call__(self, study, name):
        return read(os.path.join(self.root, study, name) if study else
                    os.path.join(self.root, name))

    def has(self, name):
        return os.path.exists(os.path.join(self.root, name))


# --- number formatting ---------------------------------------------------------------------

def g(x, digits=3):
    """A measured number with `digits` significant digits, in plain or e-notation."""
    if x is None:
        return "n/a"
    if isinstance(x, str):
        return x
    if math.isinf(x):
        return "∞"
    if x == 0:
        return "0"
    a = abs(x)
    if 1e-3 <= a < 1e5:
        s = f"{x:.{digits}g}"
        if "e" in s:  # .3g of 12345 gives 1.23e+04
            s = f"{x:.0f}"
        return s
    m, e = f"{x:.{digits - 1}e}".split("e")
    m = m.rstrip("0").rstrip(".")
    return f"{m}e{int(e)}"


def grouped(n):
    """An integer with thin groups of three digits (1 113 435)."""
    return f"{int(round(n)):,}".replace(",", " ")


def pct(x, digits=2):
    """A relative error as a percentage; below 1e-4 as a plain relative number."""
    if x is not None and abs(x) < 1e-4:
        return g(x, digits) + " (relative)"
    return g(100 * x, digits) + " %"


def nbytes(b):
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if b >= scale:
            return f"{g(b / scale, 3)} {unit}"
    return f"{int(b)} B"


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def fit_slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx


def save(fig, figures, name):
    fig.tight_layout()
    fig.savefig(os.path.join(figures, name), dpi=DPI, bbox_inches="tight")
    plt.close(fig)


# --- the studies: each returns its values for the template and draws its figures ------------

def validity(d, figures, v):
    rows = d("validity", "validity.csv")
    v["validity_table"] = table(
        ["case", "quantity", "analytic", "measured", "relative error", "tolerance", ""],
        [[f"`{r['case']}`", r["quantity"], g(r["analytic"], 7), g(r["measured"], 7),
          g(r["relative_error"], 2), g(r["tolerance"], 1),
          "pass" if r["relative_error"] <= r["tolerance"] else "**FAIL**"] for r in rows])
    v["validity_cases"] = str(len(rows))
    v["validity_passed"] = str(sum(r["relative_error"] <= r["tolerance"] for r in rows))
    by = {r["case"]: r for r in rows}
    v["validity_order"] = g(by["convergence_order"]["measured"], 5)
    v["validity_worst_margin"] = g(min(r["tolerance"] / max(r["relative_error"], 1e-300)
                                       for r in rows), 2)
    for r in rows:
        v[f"validity_{r['case']}_error"] = g(r["relative_error"], 2)

    fig, ax = plt.subplots(figsize=(7, 3.2))
    names = [r["case"].replace("_", " ") for r in rows]
    errs = [max(r["relative_error"], 1e-17) for r in rows]
    ax.barh(names, errs, color="tab:blue", label="measured relative error")
    ax.scatter([r["tolerance"] for r in rows], names, marker="|", s=300, color="tab:red",
               label="tolerance held by the tests", zorder=3)
    ax.set_xscale("log")
    ax.set_xlabel("relative error against the closed form")
    ax.invert_yaxis()
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.22), ncol=2, fontsize=8)
    ax.set_title("Physical validity: leapfrog against analytic solutions")
    save(fig, figures, "validity.png")


def integrators(d, figures, v):
    # Stability: the largest stable step against stiffness (1 g on a spring).
    rows = d("integrators", "stability.csv")
    fig, ax = plt.subplots(figsize=(7, 4))
    notes = []
    for s in SCHEMES:
        labelled = False
        for z, style in ((0.0, "-"), (0.01, ":")):
            pts = [(r["stiffness_N_per_m"], r["max_stable_step_s"]) for r in rows
                   if r["scheme"] == s and r["damping_Ns_per_m"] == z]
            finite = [(k, h) for k, h in pts if h and math.isfinite(h)]
            if finite:
                label = None
                if not labelled:
                    label = s.replace("_", " ") + ("" if z == 0 else " (damped only)")
                    labelled = True
                ax.plot(*zip(*finite), style, color=COLOURS[s], label=label)
            if pts and not finite:
                notes.append(f"{s.replace('_', ' ')}, {g(z)} N·s/m: "
                             + ("every step stable" if all(math.isinf(h) for _, h in pts)
                                else "no stable step"))
    ax.text(0.02, 0.03, "\n".join(notes), transform=ax.transAxes, fontsize=7, va="bottom")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("stiffness k (N/m), mass 1 g")
    ax.set_ylabel("largest stable step h* (s)")
    ax.set_title("Stability limit (solid: undamped; dotted: 0.01 N·s/m)")
    ax.legend(fontsize=8, loc="upper right")
    save(fig, figures, "stability.png")
    m = rows[0]["mass_kg"]

    def limit_times_omega(scheme):
        r = [r for r in rows if r["scheme"] == scheme and r["damping_Ns_per_m"] == 0][0]
        return r["max_stable_step_s"] * math.sqrt(r["stiffness_N_per_m"] / m)

    v["stab_leapfrog_hw"] = g(limit_times_omega("leapfrog"), 4)
    v["stab_rk4_hw"] = g(limit_times_omega("rk4"), 4)
    v["stab_verlet_hw"] = g(limit_times_omega("velocity_verlet"), 4)
    v["stab_symplectic_hw"] = g(limit_times_omega("symplectic_euler"), 4)
    ee = [r for r in rows if r["scheme"] == "explicit_euler" and r["damping_Ns_per_m"] == 0]
    v["stab_explicit_undamped"] = g(max(r["max_stable_step_s"] for r in ee))
    ie = [r["max_stable_step_s"] for r in rows if r["scheme"] == "implicit_euler"]
    v["stab_implicit"] = ("stable at every step (∞ in the CSV)" if all(math.isinf(h) for h in ie)
                          else f"stable up to {g(min(ie))} s")
    k1e4 = [r for r in rows if r["scheme"] == "leapfrog" and r["damping_Ns_per_m"] == 0
            and abs(r["stiffness_N_per_m"] - 1e4) < 1]
    v["stab_leapfrog_1e4"] = g(k1e4[0]["max_stable_step_s"]) if k1e4 else "n/a"
    eed = [r for r in rows if r["scheme"] == "explicit_euler" and r["damping_Ns_per_m"] > 0]
    v["stab_explicit_damped_1e4"] = g([r["max_stable_step_s"] for r in eed
                                       if abs(r["stiffness_N_per_m"] - 1e4) < 1][0])

    # Accuracy: global error at t = 1 s against the step; orders fitted.
    rows = d("integrators", "accuracy.csv")
    fig, ax = plt.subplots(figsize=(7, 4))
    order_rows = []
    for s in SCHEMES:
        pts = [(r["step_s"], r["error_at_1s_m"]) for r in rows if r["scheme"] == s]
        # Above the rounding floor (1e-11 m on a 0.1 m amplitude) the slope is the order.
        usable = [(h, e) for h, e in pts if e and e > 1e-11 and math.isfinite(e)]
        order = fit_slope(*zip(*usable)) if len(usable) >= 2 else float("nan")
        v[f"order_{s}"] = f"{order:.2f}"
        order_rows.append([s.replace("_", " "), THEORY_ORDER[s], f"{order:.2f}", len(usable),
                           g(min(e for _, e in pts)), g(max(e for _, e in pts))])
        ax.plot(*zip(*pts), "o-", ms=3, color=COLOURS[s],
                label=f"{s.replace('_', ' ')}: {order:.2f}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("step h (s)")
    ax.set_ylabel("|x(1 s) - exact| (m)")
    ax.set_title("Global error at t = 1 s (ω = 5 rad/s); legend: fitted order")
    ax.legend(fontsize=8)
    save(fig, figures, "accuracy.png")
    off = [r[0] for r in order_rows if abs(float(r[2]) - r[1]) > 0.1 * r[1]]
    v["order_claim"] = ("Every scheme shows its theoretical order (within 10 %)." if not off else
                        "Off their theoretical order by more than 10 %: " + ", ".join(off) + ".")
    lf = {r["step_s"]: r["error_at_1s_m"] for r in rows if r["scheme"] == "leapfrog"}
    ratios = [r["error_at_1s_m"] / lf[r["step_s"]] for r in rows
              if THEORY_ORDER[r["scheme"]] == 1 and lf.get(r["step_s"])]
    v["first_order_over_leapfrog"] = f"{g(min(ratios), 2)} to {g(max(ratios), 2)}"
    rk4 = sorted((r["step_s"], r["error_at_1s_m"]) for r in rows if r["scheme"] == "rk4")
    v["rk4_smallest_error"] = g(rk4[0][1], 2)
    v["order_table"] = table(["scheme", "theory", "measured order", "points fitted",
                              "smallest error (m)", "largest error (m)"], order_rows)

    # Energy after 50 periods at 50 steps a period.
    rows = d("integrators", "energy.csv")
    fig, ax = plt.subplots(figsize=(7, 3.2))
    names = [r["scheme"].replace("_", " ") for r in rows]
    ratios = [r["energy_ratio"] for r in rows]
    ax.barh(names, ratios, color=[COLOURS[r["scheme"]] for r in rows])
    ax.axvline(1, color="black", lw=0.8)
    for i, r in enumerate(rows):
        ax.text(r["energy_ratio"], i, " " + g(r["energy_ratio"], 4), va="center", fontsize=8,
                ha="right" if r["energy_ratio"] > 1e6 else "left",
                color="white" if r["energy_ratio"] > 1e6 else "black")
    ax.set_xscale("log")
    ax.set_xlabel(f"E(after {int(rows[0]['periods'])} periods) / E(0), "
                  f"{int(rows[0]['steps_per_period'])} steps a period, undamped")
    ax.invert_yaxis()
    ax.set_title("Energy drift")
    save(fig, figures, "energy.png")
    for r in rows:
        v[f"energy_{r['scheme']}"] = g(r["energy_ratio"], 4)
    v["energy_periods"] = str(int(rows[0]["periods"]))
    v["energy_steps_per_period"] = str(int(rows[0]["steps_per_period"]))

    # Cost per step.
    rows = d("integrators", "cost.csv")
    fig, ax = plt.subplots(figsize=(7, 3.2))
    names = [r["scheme"].replace("_", " ") for r in rows]
    ax.barh(names, [r["ns_per_particle_step"] for r in rows],
            color=[COLOURS[r["scheme"]] for r in rows])
    for i, r in enumerate(rows):
        extra = f", {int(r['cg_iterations'])} CG its" if r["cg_iterations"] else ""
        passes = int(r["force_passes"])
        ax.text(r["ns_per_particle_step"],
                i, f" {g(r['ns_per_particle_step'])} ns: {passes} force pass"
                f"{'es' if passes > 1 else ''}{extra}",
                va="center", fontsize=8)
    ax.set_xlim(right=max(r["ns_per_particle_step"] for r in rows) * 1.6)
    ax.invert_yaxis()
    threads = int(rows[0]["threads"])
    ax.set_xlabel(f"ns per particle-step ({int(rows[0]['points'])} points, "
                  f"{threads} thread{'s' if threads > 1 else ''})")
    ax.set_title("Cost of one step, flag in wind")
    save(fig, figures, "cost.png")
    by = {r["scheme"]: r for r in rows}
    v["cost_points"] = grouped(rows[0]["points"])
    for s in SCHEMES:
        v[f"cost_{s}"] = g(by[s]["ns_per_particle_step"], 3)
    v["cost_implicit_cg"] = str(int(by["implicit_euler"]["cg_iterations"]))
    v["cost_implicit_over_leapfrog"] = g(by["implicit_euler"]["ns_per_particle_step"] /
                                         by["leapfrog"]["ns_per_particle_step"], 3)
    v["cost_rk4_over_leapfrog"] = g(by["rk4"]["ns_per_particle_step"] /
                                    by["leapfrog"]["ns_per_particle_step"], 2)

    # The crossover: wall time per simulated second at each scheme's usable step.
    rows = d("integrators", "crossover.csv")
    ks = sorted({r["stiffness_N_per_m"] for r in rows})
    fig, ax = plt.subplots(figsize=(7, 4))
    for s in ["leapfrog", "symplectic_euler", "velocity_verlet", "rk4", "implicit_euler"]:
        pts = [(r["stiffness_N_per_m"], r["wall_s_per_simulated_s"]) for r in rows
               if r["scheme"] == s and r["wall_s_per_simulated_s"] is not None]
        if pts:
            ax.plot(*zip(*pts), "o-", color=COLOURS[s], label=s.replace("_", " "))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("stiffness (N/m), flag 24 x 16 hanging 3 s")
    ax.set_ylabel("wall s per simulated s")
    ax.set_title("Explicit at 90 % of its limit vs implicit at its usable step")
    ax.legend(fontsize=8)
    save(fig, figures, "crossover.png")
    out, first_win = [], None
    for k in ks:
        lf = [r for r in rows if r["stiffness_N_per_m"] == k and r["scheme"] == "leapfrog"][0]
        ie = [r for r in rows if r["stiffness_N_per_m"] == k and r["scheme"] == "implicit_euler"][0]
        if ie["wall_s_per_simulated_s"] is not None:
            ratio = lf["wall_s_per_simulated_s"] / ie["wall_s_per_simulated_s"]
            step = ie["step_s"]
            step_s = f"1/{round(1 / step)} s" if step > 0 else "n/a"
            cell = f"{g(ie['wall_s_per_simulated_s'])} ({step_s})"
            if ratio > 1 and first_win is None:
                first_win = k
        else:
            ratio, cell = None, "no usable step"
        out.append([g(k, 2), g(lf["leapfrog_limit_s"], 2), g(lf["wall_s_per_simulated_s"]),
                    cell, (g(ratio, 2) + "x") if ratio else "n/a"])
    v["crossover_table"] = table(["stiffness (N/m)", "leapfrog limit (s)",
                                  "leapfrog (wall s / sim s)", "implicit Euler (step)",
                                  "implicit speed-up"], out)
    below = [k for k in ks if first_win is None or k < first_win]
    if first_win is None:
        v["crossover_claim"] = ("In this run implicit Euler never beat leapfrog at comparable "
                                "quality.")
    elif not below:
        v["crossover_claim"] = (f"Implicit Euler is already faster at the softest flag "
                                f"measured ({g(first_win, 2)} N/m).")
    else:
        v["crossover_claim"] = (f"Implicit Euler starts to win between {g(max(below), 2)} and "
                                f"{g(first_win, 2)} N/m; below, leapfrog is cheaper.")
    best = max((o for o in out if o[4] != "n/a"), key=lambda o: float(o[4][:-1]), default=None)
    v["crossover_best"] = f"{best[4]} at {best[0]} N/m" if best else "n/a"
    beats = []
    for s in ["symplectic_euler", "velocity_verlet", "rk4"]:
        for k in ks:
            lf = [r for r in rows if r["stiffness_N_per_m"] == k and r["scheme"] == "leapfrog"][0]
            o = [r for r in rows if r["stiffness_N_per_m"] == k and r["scheme"] == s][0]
            if o["wall_s_per_simulated_s"] and o["comparable"] and \
                    o["wall_s_per_simulated_s"] < lf["wall_s_per_simulated_s"]:
                beats.append(f"{s.replace('_', ' ')} at {g(k, 2)} N/m")
    hi = [s for s in beats if not s.startswith("symplectic")]
    v["crossover_higher_order"] = (
        "on the hanging flag neither beats leapfrog's wall time" if not hi else
        "on the hanging flag they beat leapfrog's wall time only in " + ", ".join(hi))
    v["crossover_stiffnesses"] = ", ".join(g(k, 2) for k in ks)
    worst = min((o for o in out if o[4] != "n/a"), key=lambda o: float(o[4][:-1]), default=None)
    v["crossover_worst"] = f"{worst[4]} at {worst[0]} N/m" if worst else "n/a"


def self_collision(d, figures, v):
    rows = d("self-collision", "scaling.csv")
    phases = ["brute", "uniform", "hashed", "hierarchical"]
    threads = sorted({int(r["threads"]) for r in rows})
    fig, ax = plt.subplots(figsize=(7, 4))
    for b in phases:
        for t, style in zip(threads, ["o-", "s--"]):
            pts = [(r["particles"], r["ns_per_particle_pass"]) for r in rows
                   if r["broad_phase"] == b and int(r["threads"]) == t]
            if pts:
                ax.plot(*zip(*pts), style, color=COLOURS[b],
                        label=f"{b}, {t} thread{'s' if t > 1 else ''}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("particles (crumpled cloth)")
    ax.set_ylabel("ns per particle per pass")
    ax.set_title("Self-collision: broad phases against particle count")
    ax.legend(fontsize=7, ncol=2)
    save(fig, figures, "self_collision_scaling.png")
    one = [r for r in rows if int(r["threads"]) == 1]
    sizes = sorted({r["particles"] for r in one})
    out = []
    for n in sizes:
        cells = []
        for b in phases:
            r = [r for r in one if r["particles"] == n and r["broad_phase"] == b]
            cells.append(g(r[0]["ns_per_particle_pass"]) if r else "skipped")
        out.append([grouped(n)] + cells)
    v["sc_scaling_table"] = table(["particles"] + phases, out)
    brute = {r["particles"]: r["ns_per_particle_pass"] for r in one if r["broad_phase"] == "brute"}
    uni = {r["particles"]: r["ns_per_particle_pass"] for r in one if r["broad_phase"] == "uniform"}
    common = max(n for n in brute if n in uni)
    v["sc_brute_over_uniform"] = g(brute[common] / uni[common], 3)
    v["sc_brute_over_uniform_n"] = grouped(common)
    v["sc_uniform_growth"] = g(uni[max(uni)] / uni[min(uni)], 3)
    v["sc_uniform_n_min"], v["sc_uniform_n_max"] = grouped(min(uni)), grouped(max(uni))
    hashed = {r["particles"]: r["ns_per_particle_pass"] for r in one
              if r["broad_phase"] == "hashed"}
    slower = [n for n in hashed if n in uni and hashed[n] > uni[n]]
    v["sc_hashed_claim"] = (
        "is slower than the uniform grid at every size measured here" if len(slower) == len(hashed)
        else f"is slower than the uniform grid at {len(slower)} of {len(hashed)} sizes measured")
    fastest = {}
    big = max(sizes)
    for r in one:
        if r["particles"] == big:
            fastest[r["broad_phase"]] = r["ns_per_particle_pass"]
    v["sc_fastest_at_max"] = min(fastest, key=fastest.get)
    v["sc_max_particles"] = grouped(big)
    two = [r for r in rows if int(r["threads"]) == 2]
    if two:
        speedups = []
        for r in two:
            r1 = [q for q in one if q["particles"] == r["particles"] and
                  q["broad_phase"] == r["broad_phase"]][0]
            speedups.append(r1["ns_per_particle_pass"] / r["ns_per_particle_pass"])
        v["sc_two_threads"] = (
            f"- **The second thread** gains little in self-collision: {g(min(speedups), 2)}x to "
            f"{g(max(speedups), 2)}x (the pass is memory-bound, and on a shared machine the "
            "second core is rarely free).")
    else:
        v["sc_two_threads"] = (
            "- **A second thread** was not measured in this run (`MAILLE_STUDY_THREADS=1`: on a "
            "shared 2-core machine it mostly measures the neighbours); docs/benchmarks.md has a "
            "two-thread run, where it gains little because the pass is memory-bound.")

    # Cell size against the P n^2 model, the tuner's choice marked.
    rows = d("self-collision", "cell_size.csv")
    fig, ax = plt.subplots(figsize=(7, 4))
    ax2 = ax.twinx()
    for b in ["uniform", "hashed"]:
        fixed = [r for r in rows if r["broad_phase"] == b and r["tuner_choice"] == 0]
        auto = [r for r in rows if r["broad_phase"] == b and r["tuner_choice"] == 1]
        ax.plot([r["cell_factor"] for r in fixed], [r["measured_ns"] * 1e-6 for r in fixed],
                "o-", color=COLOURS[b], label=f"{b}: measured")
        ax2.plot([r["cell_factor"] for r in fixed], [r["model_P_n2"] for r in fixed], "x:",
                 color=COLOURS[b], label=f"{b}: P·n² model")
        if auto:
            ax.plot(auto[0]["cell_factor"], auto[0]["measured_ns"] * 1e-6, "*", ms=16,
                    color=COLOURS[b], markeredgecolor="black", label=f"{b}: tuner's choice")
    ax.set_xlabel("cell size / contact radius")
    ax.set_ylabel("ms per pass")
    ax2.set_ylabel("P·n² (occupied cells x per-cell pairs)")
    ax.set_yscale("log")
    ax2.set_yscale("log")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper left")
    n = int(rows[0]["side"])
    ax.set_title(f"Cell size: measured cost and model, {n}² crumpled cloth")
    save(fig, figures, "self_collision_cell_size.png")
    out = []
    for r in rows:
        if r["broad_phase"] != "uniform":
            continue
        out.append(["**auto** (tuner: " + g(r["cell_factor"], 3) + ")" if r["tuner_choice"]
                    else g(r["cell_factor"], 3), grouped(r["occupied_cells"]),
                    g(r["particles_per_cell"]), g(r["model_P_n2"]), g(r["measured_ns"] * 1e-6)])
    v["sc_cell_table"] = table(["cell / radius", "occupied cells", "n per cell", "P·n²",
                                "measured (ms)"], out)
    v["sc_cell_side"] = str(n)
    for b in ["uniform", "hashed"]:
        fixed = [r for r in rows if r["broad_phase"] == b and r["tuner_choice"] == 0]
        auto = [r for r in rows if r["broad_phase"] == b and r["tuner_choice"] == 1][0]
        best = min(fixed, key=lambda r: r["measured_ns"])
        v[f"sc_{b}_auto_factor"] = g(auto["cell_factor"], 3)
        v[f"sc_{b}_best_factor"] = g(best["cell_factor"], 3)
        v[f"sc_{b}_auto_over_best"] = g(auto["measured_ns"] / best["measured_ns"], 3)
        model_best = min(fixed, key=lambda r: r["model_P_n2"])
        v[f"sc_{b}_model_best_factor"] = g(model_best["cell_factor"], 3)
        pairs = agree = 0
        for i, p in enumerate(fixed):
            for q in fixed[i + 1:]:
                pairs += 1
                agree += (p["model_P_n2"] - q["model_P_n2"]) * \
                    (p["measured_ns"] - q["measured_ns"]) > 0
        v[f"sc_{b}_model_agrees"] = f"{agree} of {pairs}"

    # Exclusions and memory.
    rows = d("self-collision", "exclusion.csv")
    v["sc_exclusion_table"] = table(
        ["exclusion", "distance tests", "pairs excluded one by one", "cell pairs skipped",
         "contacts", "memory", "ns per particle"],
        [[r["exclusion"], grouped(r["candidate_pairs"]), grouped(r["excluded_pairs"]),
          grouped(r["skipped_cells"]), grouped(r["contacts"]), nbytes(r["exclusion_bytes"]),
          g(r["ns_per_particle_pass"])] for r in rows])
    v["sc_exclusion_side"] = str(int(rows[0]["side"]))
    ex = {r["exclusion"]: r for r in rows}
    same = ex["matrix"]["contacts"] == ex["signature"]["contacts"]
    v["sc_same_contacts"] = (
        f"the same {grouped(ex['matrix']['contacts'])} contacts (of "
        f"{grouped(ex['none']['contacts'])} without exclusion)" if same else
        f"different contacts ({grouped(ex['matrix']['contacts'])} against "
        f"{grouped(ex['signature']['contacts'])})")
    m_, s_ = ex["matrix"], ex["signature"]
    if s_["ns_per_particle_pass"] > m_["ns_per_particle_pass"]:
        v["sc_signature_time"] = (
            f"- **The signature exclusion's pass is slower** than the matrix's in this run: "
            f"{g(s_['ns_per_particle_pass'])} against {g(m_['ns_per_particle_pass'])} ns per "
            f"particle ({grouped(s_['candidate_pairs'])} distance tests against "
            f"{grouped(m_['candidate_pairs'])}): it pays for its memory with time.")
    else:
        v["sc_signature_time"] = ""
    v["sc_matrix_over_signature_memory"] = g(ex["matrix"]["exclusion_bytes"] /
                                             ex["signature"]["exclusion_bytes"], 3)
    rows = d("self-collision", "memory.csv")
    fig, ax = plt.subplots(figsize=(7, 3.5))
    counts = sorted({r["particles"] for r in rows})
    width = 0.27
    for i, (label, colour, get) in enumerate([
            ("matrix (rows)", "tab:orange",
             lambda n: [r["bytes"] for r in rows if r["particles"] == n and
                        r["exclusion"] == "matrix"][0]),
            ("signature", "tab:blue",
             lambda n: [r["bytes"] for r in rows if r["particles"] == n and
                        r["exclusion"] == "signature"][0]),
            ("dense bit matrix", "tab:grey",
             lambda n: [r["dense_bit_matrix_bytes"] for r in rows if r["particles"] == n][0])]):
        vals = [get(n) for n in counts]
        xs = [j + (i - 1) * width for j in range(len(counts))]
        ax.bar(xs, vals, width, label=label, color=colour)
        for x, val in zip(xs, vals):
            ax.text(x, val, nbytes(val), ha="center", va="bottom", fontsize=7)
    ax.set_xticks(range(len(counts)), [f"{grouped(n)} particles" for n in counts])
    ax.set_yscale("log")
    ax.set_ylabel("bytes")
    ax.set_title("Memory of the topological exclusion")
    ax.legend(fontsize=8)
    save(fig, figures, "self_collision_memory.png")
    out = []
    for n in counts:
        m = [r for r in rows if r["particles"] == n and r["exclusion"] == "matrix"][0]
        s = [r for r in rows if r["particles"] == n and r["exclusion"] == "signature"][0]
        out.append([grouped(n), nbytes(m["bytes"]), g(m["bytes_per_particle"]), nbytes(s["bytes"]),
                    g(s["bytes_per_particle"]), nbytes(m["dense_bit_matrix_bytes"])])
    v["sc_memory_table"] = table(["particles", "matrix", "bytes/particle", "signature",
                                  "bytes/particle", "dense bit matrix"], out)

    rows = d("self-collision", "flag_wind.csv")
    fw = {r["self_collision"]: r for r in rows}
    v["sc_flag_off"] = g(fw["off"]["ns_per_particle_step"])
    v["sc_flag_on"] = g(fw["on"]["ns_per_particle_step"])
    v["sc_flag_ratio"] = g(fw["on"]["ns_per_particle_step"] / fw["off"]["ns_per_particle_step"], 3)
    v["sc_flag_steps"] = str(int(fw["on"]["steps"]))
    intersections(d, v)


def intersections(d, v):
    """Every self-colliding example with and without its self-collision: the most crossing
    pairs of triangles over the run and the cost (intersections.csv)."""
    rows = d("self-collision", "intersections.csv")
    by = {}
    for r in rows:
        by.setdefault(r["example"], {})[r["self_collision"]] = r
    out, crossing_without, crossing_with, ratios = [], 0, 0, []
    for name in sorted(by):
        on, off = by[name].get("on"), by[name].get("off")
        if not on or not off:
            continue
        scheme = on["integrator"] + (f" ({on['solver']})" if on["solver"] else "")

        def crossings(r):
            n = int(r["most_intersecting_pairs"])
            return f"{n} (first at {g(r['first_crossing_s'], 2)} s)" if n else "0"
        ratio = on["wall_s"] / off["wall_s"] if off["wall_s"] > 0 else float("nan")
        ratios.append(ratio)
        crossing_without += int(off["most_intersecting_pairs"]) > 0
        crossing_with += int(on["most_intersecting_pairs"]) > 0
        out.append([name, scheme, g(on["step"], 2), g(on["simulated_s"], 3), crossings(off),
                    crossings(on), g(off["wall_s"], 3), g(on["wall_s"], 3), g(ratio, 3)])
    v["sc_intersections_table"] = table(
        ["example", "scheme", "step (s)", "simulated (s)", "crossing pairs without",
         "crossing pairs with", "wall s without", "wall s with", "cost"], out)
    v["sc_intersections_claim"] = (
        f"Of the {len(out)} self-colliding examples, {crossing_without} cross without their "
        f"self-collision and {crossing_with} with it; self-collision costs "
        f"{g(min(ratios), 3)}x to {g(max(ratios), 3)}x the run without it.")


def obstacles(d, figures, v):
    rows = d("obstacles", "obstacles.csv")
    shapes = list(dict.fromkeys(r["shape"] for r in rows))
    methods = ["geometric", "facets", "conditional"]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.6))
    width = 0.27
    for i, m in enumerate(methods):
        xs = [j + (i - 1) * width for j in range(len(shapes))]
        pen = [[r for r in rows if r["shape"] == s and r["method"] == m][0]
               ["max_penetration_m"] * 1e3 for s in shapes]
        cost = [[r for r in rows if r["shape"] == s and r["method"] == m][0]["obstacle_ns_pps"]
                for s in shapes]
        ax1.bar(xs, pen, width, color=COLOURS[m], label=m)
        ax2.bar(xs, cost, width, color=COLOURS[m], label=m)
        for x, p_ in zip(xs, pen):
            ax1.text(x, p_, g(p_, 2), ha="center", va="bottom", fontsize=7)
    for ax in (ax1, ax2):
        ax.set_xticks(range(len(shapes)), [s.replace("_", " ") for s in shapes])
    ax1.set_ylabel("deepest penetration (mm)")
    ax1.set_title("Penetration into the true shape")
    ax2.set_ylabel("obstacle stage, ns per particle-step")
    ax2.set_title("Cost")
    ax1.legend(fontsize=8)
    save(fig, figures, "obstacles.png")
    v["obs_table"] = table(
        ["shape", "method", "deepest penetration (mm)", "mean contacts per step",
         "obstacle (ns/pps)", "links (ns/pps)"],
        [[r["shape"].replace("_", " "), r["method"], g(r["max_penetration_m"] * 1e3),
          g(r["mean_contacts"]), g(r["obstacle_ns_pps"]), g(r["link_ns_pps"])] for r in rows])
    v["obs_particles"] = grouped(rows[0]["particles"])
    v["obs_seconds"] = g(rows[0]["steps"] * 2e-4, 2)
    for m in methods:
        mr = [r for r in rows if r["method"] == m]
        v[f"obs_{m}_max_pen_mm"] = g(max(r["max_penetration_m"] for r in mr) * 1e3)
        v[f"obs_{m}_cost"] = (f"{g(min(r['obstacle_ns_pps'] for r in mr))}–"
                              f"{g(max(r['obstacle_ns_pps'] for r in mr))}")
    facets_cubes = [r["max_penetration_m"] for r in rows
                    if r["method"] == "facets" and r["shape"] != "sphere"]
    v["obs_facets_cubes_mm"] = g(max(facets_cubes) * 1e3)
    cheapest = min(methods, key=lambda m: sum(r["obstacle_ns_pps"] for r in rows
                                              if r["method"] == m))
    shallowest = min(methods, key=lambda m: max(r["max_penetration_m"] for r in rows
                                                if r["method"] == m))
    v["obs_cheapest"], v["obs_shallowest"] = cheapest, shallowest

    rows = d("obstacles", "incline.csv")
    fig, ax = plt.subplots(figsize=(7, 3.4))
    labels = [f"{r['method']}\nμ = {g(r['mu'], 2)}" for r in rows]
    xs = range(len(rows))
    ax.bar([x - 0.2 for x in xs], [r["distance_m"] for r in rows], 0.4, label="measured",
           color="tab:blue")
    ax.bar([x + 0.2 for x in xs], [r["analytic_m"] for r in rows], 0.4,
           label="analytic ½ g (sin θ − μ cos θ) T²", color="tab:grey")
    for x, r in zip(xs, rows):
        ax.text(x, max(r["distance_m"], r["analytic_m"]), "error " + g(r["relative_error"], 2),
                ha="center", va="bottom", fontsize=7)
    ax.set_xticks(list(xs), labels, fontsize=8)
    ax.set_ylabel(f"distance slid in {g(rows[0]['seconds'], 2)} s (m)")
    ax.set_title(f"A bead on a {g(rows[0]['theta_deg'], 2)}° incline (labels: relative error)")
    ax.set_ylim(top=max(max(r["distance_m"], r["analytic_m"]) for r in rows) * 1.35)
    ax.legend(fontsize=8, loc="upper right")
    save(fig, figures, "incline.png")
    v["incline_table"] = table(
        ["method", "μ", "slid (m)", "analytic (m)", "relative error"],
        [[r["method"], g(r["mu"], 2), g(r["distance_m"], 4), g(r["analytic_m"], 4),
          pct(r["relative_error"])] for r in rows])
    v["incline_facets_worst"] = pct(max(r["relative_error"] for r in rows
                                        if r["method"] == "facets"))
    v["incline_geometric"] = pct(max(r["relative_error"] for r in rows
                                     if r["method"] == "geometric"))
    v["incline_theta"] = g(rows[0]["theta_deg"], 2)
    v["incline_seconds"] = g(rows[0]["seconds"], 2)
    v["incline_worst"] = pct(max(r["relative_error"] for r in rows))
    worst = max(rows, key=lambda r: r["relative_error"])
    v["incline_worst_case"] = f"{worst['method']}, μ = {g(worst['mu'], 2)}"

    rows = d("obstacles", "lean.csv")
    v["lean_table"] = table(
        ["scale (x, y, z)", "mean lean (°)", "largest lean (°)"],
        [[f"({g(r['scale_x'], 2)}, {g(r['scale_y'], 2)}, {g(r['scale_z'], 2)})",
          g(r["mean_lean_deg"]), g(r["max_lean_deg"])] for r in rows])
    v["lean_max"] = g(max(r["max_lean_deg"] for r in rows))


SOLVER_COLOURS = {"leapfrog": "tab:blue", "matrix_free": "tab:orange", "vbd": "tab:green",
                  "vbd, sweeps only": "tab:olive", "bullet": "tab:red"}


def solver_name(r):
    """A large-steps row's solver: VBD without its coarse correction is "vbd, sweeps only"."""
    return "vbd, sweeps only" if r["solver"] == "vbd" and r.get("coarse") == "off" \
        else r["solver"]


def iterations_label(r):
    """A large-steps row's iterations: VBD's sweeps, matrix_free's Newton iterations (past 1)."""
    if r["solver"] == "vbd":
        return f" {int(r['iterations'])} sweeps"
    if r["solver"] == "matrix_free" and r["iterations"] > 1:
        return f" {int(r['iterations'])} Newton"
    return ""


def threads_of(r):
    """A large-steps row's thread count (rows written before the column existed: one)."""
    return int(r.get("threads") or 1)


def threads_label(r):
    return f", {threads_of(r)} threads" if threads_of(r) > 1 else ""


def large_steps(d, figures, v):
    """Implicit Euler at animation steps against leapfrog at its limit (and Bullet on the
    sphere scene when peer.csv exists): the table and wall time against stretch."""
    rows = d("large-steps", "large_steps.csv")
    bullet = [r for r in d(None, "peer.csv") if r["engine"] == "bullet"] \
        if d.has("peer.csv") else []
    fig, axes = plt.subplots(1, 3, figsize=(14, 3.8), sharey=True)
    for ax, scene in zip(axes, ["sphere", "heap", "drape"]):
        for r in rows:
            if r["scene"] != scene or not r["stable"]:
                continue
            label = solver_name(r) + iterations_label(r) + threads_label(r)
            ax.scatter(r["max_stretch"] * 100, r["wall_s_per_sim_s"],
                       color=SOLVER_COLOURS[solver_name(r)], s=10 + 20 * math.log2(
                           max(r["particles"], 1024) / 512),
                       marker="o" if r["iterations"] <= 1 or (r["solver"] == "vbd" and
                                                             r["iterations"] <= 10) else "s",
                       label=label)
            ax.annotate(f"1/{round(1 / r['step_s'])}" if r["step_s"] > 1e-3 else "",
                        (r["max_stretch"] * 100, r["wall_s_per_sim_s"]), fontsize=6)
        if scene == "sphere":
            for r in bullet:
                if r["stable"] and r["max_stretch"] is not None:
                    ax.scatter(r["max_stretch"] * 100, r["wall_s_per_sim_s"],
                               color=SOLVER_COLOURS["bullet"], marker="^",
                               label=f"Bullet {r['setting']}")
        handles, labels = ax.get_legend_handles_labels()
        seen = dict(zip(labels, handles))
        ax.legend(seen.values(), seen.keys(), fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("largest structural stretch (%)")
        ax.set_title({"sphere": "Cloth on a sphere", "heap": "Self-colliding heap",
                      "drape": "Self-colliding drape, 64²"}[scene])
    axes[0].set_ylabel("wall s per simulated s (one thread unless marked)")
    save(fig, figures, "large_steps.png")
    v["large_steps_table"] = table(
        ["scene", "particles", "solver", "step (s)", "sweeps / Newton its", "wall s / sim s",
         "largest stretch", "deepest penetration (mm)", "kinetic energy left (J)",
         "largest residual (m g)", "stable", "threads"],
        [[r["scene"], grouped(r["particles"]), solver_name(r), g(r["step_s"]),
          str(int(r["iterations"])) if r["iterations"] else "",
          g(r["wall_s_per_sim_s"]), pct(r["max_stretch"]),
          g(r["max_penetration_m"] * 1e3), g(r["final_kinetic_J"]),
          g(r["max_residual"]) if r["solver"] != "leapfrog" else "",
          "yes" if r["stable"] else "**no**", str(threads_of(r))] for r in rows])
    # The quality bar (stretch at most 10 %, penetration at most 2 mm) at 1/60 s.
    at60 = [r for r in rows if r["solver"] != "leapfrog" and abs(r["step_s"] - 1 / 60) < 1e-6]
    good = [r for r in at60 if r["stable"] and r["max_stretch"] <= 0.1
            and r["max_penetration_m"] <= 2e-3]
    v["large_steps_at_60"] = (
        f"{len(good)} of {len(at60)} implicit runs at 1/60 s keep the largest stretch within 10 % "
        f"and the deepest penetration within 2 mm")
    v["large_steps_duration"] = g(max(r["sim_s"] for r in rows if r["scene"] != "drape"), 2)
    # The large-step target: VBD at 1/60 s (10 sweeps) at most 0.1x Bullet tuned's time on
    # the sphere, within 10 % stretch: a loss wherever a size misses it.
    missed = []
    for r in rows:
        if r["scene"] != "sphere" or r["solver"] != "vbd" or r.get("coarse") == "off" \
                or abs(r["step_s"] - 1 / 60) > 1e-6 or int(r["iterations"]) != 10:
            continue
        tuned = [b for b in bullet if b["setting"] == "tuned" and b["particles"] == r["particles"]
                 and b["stable"] and b["wall_s_per_sim_s"]]
        if not tuned:
            continue
        ratio = r["wall_s_per_sim_s"] / tuned[0]["wall_s_per_sim_s"]
        if ratio > 0.1 or r["max_stretch"] > 0.1:
            missed.append(f"{grouped(r['particles'])} particles {g(ratio, 2)}x "
                          f"({pct(r['max_stretch'])} stretch against Bullet's "
                          f"{pct(tuned[0]['max_stretch'])})")
    v["large_steps_loss"] = (
        "- **VBD is not 10x faster than Bullet** on the cloth on a sphere (the large-step target: "
        "at 1/60 s with 10 sweeps, at most 0.1x Bullet tuned's wall time within 10 % stretch): "
        + "; ".join(missed) + ". docs/implicit.md says where the time goes.") if missed else ""
    # The real-time case: the drape on two threads, the fastest run within the bar.
    drape = [r for r in rows if r["scene"] == "drape" and threads_of(r) == 2 and r["stable"]
             and r["max_stretch"] <= 0.1 and r["max_penetration_m"] <= 2e-3]
    best = min(drape, key=lambda r: r["wall_s_per_sim_s"]) if drape else None
    v["large_steps_real_time"] = (
        f"the fastest drape on two threads within that bar takes {g(best['wall_s_per_sim_s'])} s "
        f"per simulated second (h = 1/{round(1 / best['step_s'])} s, "
        f"{int(best['iterations'])} sweeps, stretch {pct(best['max_stretch'])}): "
        + ("real time" if best["wall_s_per_sim_s"] <= 1 else "slower than real time")
        if best else "no drape run on two threads stays within that bar")


def peer(d, figures, v):
    v["peer_losses"] = ""
    status = {r["key"]: r["value"] for r in d(None, "run.csv")}.get("peer") \
        if d.has("run.csv") else None
    if status == "failed":
        v["peer_section"] = (
            "The Bullet harness (`bench/peer_bullet`) was built but failed in this run (its "
            "error is in the output of `scripts/report.sh`), so there is no peer comparison "
            "here.")
        return False
    if not d.has("peer.csv"):
        v["peer_section"] = (
            "The Bullet harness (`bench/peer_bullet`) was not built for this run, so there is "
            "no peer comparison here. It is built when CMake finds Bullet (`scripts/setup.sh "
            "libbullet-dev`, then reconfigure); `scripts/report.sh` runs it whenever "
            "`build/<preset>/bench/peer_bullet` exists and this section then shows its table.")
        return False
    rows = d(None, "peer.csv")
    if not rows:
        v["peer_section"] = "`peer.csv` exists but holds no rows: the harness measured nothing."
        return False
    cols = ["engine", "version", "particles", "setting", "step_s", "wall_s_per_sim_s",
            "max_penetration_m", "max_stretch", "stable"]
    out = []
    for r in rows:
        out.append([r["engine"], g(r["version"]) if not isinstance(r["version"], str)
                    else r["version"], grouped(r["particles"]), r["setting"], g(r["step_s"]),
                    g(r["wall_s_per_sim_s"]), g(r["max_penetration_m"] * 1e3)
                    if r["max_penetration_m"] is not None else "n/a",
                    pct(r["max_stretch"]) if r["max_stretch"] is not None else "n/a",
                    "yes" if r["stable"] else "**no**"])
    text = [table(["engine", "version", "particles", "setting", "step (s)", "wall s / sim s",
                   "deepest penetration (mm)", "largest stretch", "stable"], out)]
    # Ratios between engines at the same size and setting (wall time per simulated second).
    engines = list(dict.fromkeys(r["engine"] for r in rows))
    if len(engines) >= 2:
        a, b = engines[0], engines[1]
        lines = []
        for r in rows:
            if r["engine"] != a:
                continue
            o = [q for q in rows if q["engine"] == b and q["particles"] == r["particles"]
                 and q["setting"] == r["setting"]]
            if o and r["wall_s_per_sim_s"] and o[0]["wall_s_per_sim_s"]:
                lines.append(f"- {grouped(r['particles'])} particles, {r['setting']}: {b} takes "
                             f"{g(o[0]['wall_s_per_sim_s'] / r['wall_s_per_sim_s'], 3)}x "
                             f"{a}'s wall time per simulated second.")
        if lines:
            text.append("\n".join(lines))
    v["peer_section"] = "\n\n".join(text)
    # Losses: where another engine is faster than Maille at the same size and setting, and
    # any Maille run that was not stable.
    ours = [r for r in rows if str(r["engine"]).lower() == "maille"]
    losses = []
    for r in ours:
        if not r["stable"]:
            losses.append(f"- **Maille was not stable** at {grouped(r['particles'])} particles "
                          f"({r['setting']}, step {g(r['step_s'])} s).")
        for o in rows:
            if o in ours or o["particles"] != r["particles"] or o["setting"] != r["setting"]:
                continue
            if o["stable"] and o["wall_s_per_sim_s"] and r["wall_s_per_sim_s"] and \
                    o["wall_s_per_sim_s"] < r["wall_s_per_sim_s"]:
                losses.append(
                    f"- **{o['engine']} is faster** at {grouped(r['particles'])} particles "
                    f"({r['setting']}): {g(o['wall_s_per_sim_s'])} against "
                    f"{g(r['wall_s_per_sim_s'])} wall s per simulated s (largest stretch "
                    f"{pct(o['max_stretch']) if o['max_stretch'] is not None else 'n/a'} "
                    f"against {pct(r['max_stretch']) if r['max_stretch'] is not None else 'n/a'}).")
    v["peer_losses"] = "\n".join(losses)
    fig, ax = plt.subplots(figsize=(7, 3.6))
    for e in engines:
        for s, style in (("default", "o-"), ("tuned", "s--")):
            pts = sorted((r["particles"], r["wall_s_per_sim_s"]) for r in rows
                         if r["engine"] == e and r["setting"] == s and r["wall_s_per_sim_s"])
            if pts:
                ax.plot(*zip(*pts), style, label=f"{e}, {s}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("particles")
    ax.set_ylabel("wall s per simulated s")
    ax.set_title("Peer engine: the same cloth")
    ax.legend(fontsize=8)
    save(fig, figures, "peer.png")
    return True


def gpu(d, v):
    """The CPU-against-GPU table (scripts/bench_gpu.sh): particle-steps per second by size."""
    v["gpu_loss"] = ""
    if not d.has("gpu/flags.csv"):
        v["gpu_section"] = (
            "The GPU backend did not run for this report (`maille info --backend gpu` failed: no "
            "OpenGL 4.5 driver through EGL), so there is no CPU/GPU table here.")
        return
    rows = d("gpu", "flags.csv")
    by = {(int(r["size"]), r["config"], r["self_collision"]): r for r in rows}
    sizes = sorted({int(r["size"]) for r in rows})
    gpu_names = sorted({str(r["device"]) for r in rows if r["config"] == "gpu"})
    cpu_names = sorted({str(r["device"]) for r in rows if r["config"] != "gpu"})

    def cell(r):
        if r is None:
            return "n/a"
        if r["status"] != "ok":
            return "refused" if "no GPU version" in str(r["status"]) else "failed"
        return g(r["particle_steps_per_second"])

    out, ratios = [], []
    for n in sizes:
        for sc in ("off", "on"):
            c1, ca, gp = (by.get((n, c, sc)) for c in ("cpu1", "cpuall", "gpu"))
            ratio = "n/a"
            if c1 and gp and c1["status"] == "ok" and gp["status"] == "ok":
                ratio = g(gp["particle_steps_per_second"] / c1["particle_steps_per_second"])
                ratios.append(gp["particle_steps_per_second"] / c1["particle_steps_per_second"])
            out.append([f"{n}²", "with" if sc == "on" else "without", cell(c1), cell(ca),
                        cell(gp), ratio])
    text = [f"Particle-steps per second of a square flag in gusty wind "
            f"(`bench/scenes/gpu_flag.toml`, `scripts/bench_gpu.sh`), on {', '.join(cpu_names)} "
            f"(one thread, all threads) and the GPU backend on "
            f"**{', '.join(gpu_names)}**:",
            table(["flag", "self-collision", "CPU 1 thread", "CPU all threads", "GPU",
                   "GPU / CPU 1"], out)]
    if any("llvmpipe" in n for n in gpu_names):
        text.append(
            "llvmpipe is Mesa's software driver: the GPU backend's shaders run on this machine's "
            "CPU cores, one work group per thread, so these ratios measure the backend's "
            "correctness path, not a GPU; "
            f"it runs at {g(min(ratios)) if ratios else 'n/a'}–{g(max(ratios)) if ratios else 'n/a'}x "
            "the CPU backend's one thread. The bytes each particle-step moves, and the bandwidth "
            "bound they set on a real GPU, are in [gpu.md](gpu.md#bytes-per-particle-step-and-the-bandwidth-bound).")
    if any(r["config"] == "gpu" and r["status"] != "ok" for r in rows):
        text.append("\"refused\": the scene's self-collision stage has no GPU version in this "
                    "build, and the GPU backend refuses it by name rather than run it wrongly.")
    v["gpu_section"] = "\n\n".join(text)
    if all("llvmpipe" in n or n == "unavailable" for n in gpu_names):
        v["gpu_loss"] = ("- **The GPU backend was not measured on a GPU**: section 6 ran on "
                         f"{', '.join(gpu_names)}, the CPU in disguise; how close it comes to "
                         "its bandwidth bound on a real GPU is unknown to this report.")


# The anchors' published live figures: elements at 44.1 kHz and the share of one core.
LIVE_ANCHORS = [("mi-gen~ (Max/MSP, generated code)", "506 one-dimensional masses", 0.67),
                ("Faust mass-interaction library (generated code)", "598 masses", 0.45)]
LIVE_KINDS = [("string", "string (a rope with fixed ends, `examples/play_string.toml`'s bead)"),
              ("drum", "square drum (n x n beads, fixed edges, `bench/scenes/play_square_drum.toml`)"),
              ("bar", "lattice bar (n x 3 x 3 beads, `bench/scenes/play_lattice_bar.toml`)")]


def live(d, v):
    """The largest live model per kind (scripts/bench_live.sh): a size is live when the step's
    CPU time per 64-frame period at 48 kHz has its 99th percentile at or below half the period."""
    v["live_loss"] = ""
    if not d.has("live/live.csv"):
        v["live_section"] = ("`scripts/bench_live.sh` did not run for this report: no live "
                             "figures.")
        return
    rows = d("live", "live.csv")
    out, losses = [], []
    for kind, label in LIVE_KINDS:
        mine = sorted((r for r in rows if r["kind"] == kind and r["status"] == "ok"),
                      key=lambda r: int(r["points"]))
        fits = [r for r in mine if float(r["cpu_p99"]) <= 0.5]
        best = fits[-1] if fits else None
        over = next((r for r in mine if float(r["cpu_p99"]) > 0.5), None)
        # The anchors' own measure: the mean share of a core (Faust's 45 %).
        shares = [r for r in mine if float(r["cpu_mean"]) <= 0.45]
        share = f"{grouped(int(shares[-1]['points']))} points" if shares else "none measured"
        out.append([label,
                    f"{grouped(int(best['points']))} points, {grouped(int(best['links']))} links"
                    if best else "none measured fits",
                    pct(float(best["cpu_mean"]), 1) if best else "n/a",
                    pct(float(best["cpu_p99"]), 1) if best else "n/a",
                    (f"{grouped(int(over['points']))} points: p99 {pct(float(over['cpu_p99']), 1)}"
                     if over else "none measured"), share])
        if kind == "drum" and (not best or int(best["points"]) < 1024):
            losses.append("the square drum stays under 1,024 points at half the period")
    text = ["The largest model of each kind whose step's CPU time per period "
            "(`CLOCK_THREAD_CPUTIME_ID`, 64 frames at 48 kHz, one thread, `maille play "
            "--benchmark`, `scripts/bench_live.sh`) stays at or below **half the period** at its "
            "99th percentile (every size measured: `live/live.csv` in the data):",
            table(["kind", "largest live", "CPU mean", "CPU p99", "next size measured",
                   "largest at a mean <= 45 %"], out),
            "The anchors, as published (both generate and compile code for each model, and stop "
            "near 1,000–1,800 elements when the generated code no longer compiles; Maille loads a "
            "scene with no compile step): " +
            "; ".join(f"{name}: {what} at 44.1 kHz at {pct(share, 0)} of a core"
                      for name, what, share in LIVE_ANCHORS) +
            ". Their fractions are of a whole core, not of half a period: at its 99th percentile "
            "Maille's budget here is stricter."]
    v["live_section"] = "\n\n".join(text)
    if losses:
        v["live_loss"] = ("- **Live sound below its target**: " + "; ".join(losses) +
                          " (docs/sound.md, \"A lean step\": where the step's time goes).")


def run_info(d, v):
    info = {}
    if d.has("run.csv"):
        info = {r["key"]: r["value"] for r in read(os.path.join(d.root, "run.csv"))}
    for k, val in info.items():
        v[f"run_{k}"] = g(val, 4) if isinstance(val, float) else str(val)
    for k in ("date", "commit", "preset", "cpu", "cores", "study_s", "peer_s", "gallery_s",
              "build_s", "total_s", "mode", "load"):
        v.setdefault(f"run_{k}", "n/a")
    rows = read(os.path.join(d.root, "durations.csv"))
    v["durations_table"] = table(["study", "wall time (s)"],
                                 [[r["study"], g(r["wall_s"], 3)] for r in rows])
    v["study_total_s"] = g(sum(r["wall_s"] for r in rows), 3)
    v["study_total_min"] = g(sum(r["wall_s"] for r in rows) / 60, 2)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", required=True)
    p.add_argument("--figures", required=True)
    p.add_argument("--template")
    p.add_argument("--md")
    a = p.parse_args()
    os.makedirs(a.figures, exist_ok=True)
    d = Data(a.data)
    v = {}
    validity(d, a.figures, v)
    integrators(d, a.figures, v)
    self_collision(d, a.figures, v)
    obstacles(d, a.figures, v)
    large_steps(d, a.figures, v)
    has_peer = peer(d, a.figures, v)
    gpu(d, v)
    live(d, v)
    run_info(d, v)
    written = FIGURES + (OPTIONAL_FIGURES if has_peer else [])
    missing = [f for f in written if not os.path.exists(os.path.join(a.figures, f))]
    if missing:
        sys.exit(f"report.py: figures not written: {missing}")
    if a.template and a.md:
        fig_dir = os.path.relpath(a.figures, os.path.dirname(os.path.abspath(a.md)))
        v["figures"] = fig_dir
        v["data"] = os.path.relpath(a.data, os.path.dirname(os.path.abspath(a.md)))
        v["peer_figure"] = (f"![peer engine]({fig_dir}/peer.png)" if has_peer else "")
        text = open(a.template).read()
        unknown = sorted(set(re.findall(r"\{\{(\w+)\}\}", text)) - set(v))
        if unknown:
            sys.exit(f"report.py: the template uses unknown keys: {unknown}")
        # A placeholder alone on its line whose value is empty takes its line with it.
        text = re.sub(r"^\{\{(\w+)\}\}\n", lambda m: v[m.group(1)] + "\n" if v[m.group(1)]
                      else "", text, flags=re.M)
        text = re.sub(r"\{\{(\w+)\}\}", lambda m: v[m.group(1)], text)
        with open(a.md + ".tmp", "w") as f:
            f.write(text)
        os.replace(a.md + ".tmp", a.md)
    print(f"report.py: {len(written)} figures in {a.figures}" +
          (f", {a.md}" if a.md else ""))


if __name__ == "__main__":
    main()
