#!/usr/bin/python3
"""Renders every example in examples/*.toml to a thumbnail and writes the gallery page.

    gallery.py --maille BIN --out DIR --md FILE [--quick] [--width W --height H] [--only N,...]

Each scene is rendered by `maille render SCENE --out DIR/NAME.png --duration T --width W
--height H` (headless EGL), T from GALLERY_TIME below (a moment that shows what the scene is
about) or the smaller of the scene's duration and 2 s, with GALLERY_CAMERA's view where the
automatic framing is not the best. The page (FILE) is a table: thumbnail,
name, the scene's `description`, and the exact command that reproduces the thumbnail.
--quick renders 160 x 90 thumbnails at t = 0.1 s (a check that every scene renders; for CI).
--only NAME,... renders only those scenes (a new example's thumbnail without rendering all
again); every other scene keeps the thumbnail already in DIR and its row on the page.
Exit 1 if any scene fails to render (the others are still rendered and listed).
"""
import argparse
import glob
import os
import shlex
import subprocess
import sys
import time
import tomllib

from gallery_timings import TIMINGS_BEGIN, TIMINGS_END

# Simulated time of the thumbnail, s: the moment the scene shows best.
GALLERY_TIME = {
    "flag_in_wind": 2.5, "hanging_net": 1.5, "rope_bridge": 1.5, "jelly_cube_bounce": 1.0,
    "drum_membrane": 0.3, "lattice_balls_collide": 0.8, "pendulum_chain": 0.53,
    "cloth_heap": 2.5, "cloth_heap_vbd": 2.5, "flag_storm": 3.0, "cloth_wringing": 2.5,
    "cloth_down_stairs": 3.0, "rope_coil": 3.0, "net_and_rotating_cube": 2.0, "shaken_flag": 2.0,
    "wrung_cloth": 4.0,
}

# Camera (yaw, pitch[, zoom]) where the automatic framing is not the best view; these are the
# views of the README's pictures.
GALLERY_CAMERA = {
    "cloth_heap": "35,25,0.7", "cloth_heap_vbd": "35,25,0.7", "cloth_wringing": "20,20,0.9",
    "wrung_cloth": "20,20,0.9",
    "two_cloths": "30,30,0.7",
    "flag_storm": "40,10", "tablecloth_on_table": "30,25,0.9", "cloth_down_stairs": "50,20,0.9",
    "cloth_in_bowl": "20,35,0.9", "cloth_on_torus": "30,30,0.9", "cloth_over_rock": "30,25,0.9",
    "cloth_on_cylinder": "40,20,0.9", "smooth_flag_16": "35,15,0.8", "flag_64": "35,15,0.8",
}

# The quick mode's time where 0.1 s is too long: the GPU example (262 144 particles at 25 us
# steps) on Mesa's software driver takes about 0.7 s per step.
QUICK_TIME = {"gpu_cloth_512": 0.0005}
GALLERY_TIME["gpu_cloth_512"] = 0.005
GALLERY_TIME["smooth_drum"] = 0.3

# More `maille render` flags for a scene: the 16 x 16 flag is there to be drawn smooth.
GALLERY_FLAGS = {"smooth_flag_16": ["--smooth", "--lod", "4"],
                 "smooth_drum": ["--smooth", "--lod", "6"]}

# Scenes whose stats.csv columns are plotted over their whole duration beside the thumbnail
# (`maille run SCENE --no-frames`): the wrung strip's crossing triangle pairs, which stay 0 while
# its point-triangle and edge-edge contacts act.
GALLERY_PLOTS = {
    "wrung_cloth": ["intersecting_pairs", "self_triangle_contacts", "self_edge_contacts"],
}

# The binary the page's commands name: the README's build (the thumbnails may come from another
# preset's identical build).
SHOWN_MAILLE = "build/release/apps/maille/maille"


def kept_timings(md):
    """The speed table of the page being replaced (scripts/gallery_timings.sh writes it), so
    that rendering again keeps it: lines to append, empty when the page has none."""
    if not os.path.exists(md):
        return []
    text = open(md).read()
    if TIMINGS_BEGIN not in text or TIMINGS_END not in text:
        return []
    block = text.split(TIMINGS_BEGIN, 1)[1].split(TIMINGS_END, 1)[0]
    return [""] + (TIMINGS_BEGIN + block + TIMINGS_END).split("\n")


def plot_counts(maille, path, name, columns, png):
    """Runs the scene whole without frames and plots `columns` of its stats.csv against time
    into png; returns the run's command, or None when the run or the plot failed."""
    import csv
    import tempfile

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with tempfile.TemporaryDirectory() as out:
        cmd = [maille, "run", path, "--no-frames", "--out", out]
        r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            print(f"gallery: {name}: run for its plot: exit {r.returncode}: "
                  f"{r.stderr.strip()[-300:]}", file=sys.stderr)
            return None
        with open(os.path.join(out, "stats.csv")) as f:
            rows = list(csv.DictReader(f))
    t = [float(r["time"]) for r in rows]
    fig, ax = plt.subplots(figsize=(4.8, 2.4), dpi=100)
    for c in columns:
        ax.plot(t, [float(r[c]) for r in rows], label=c, lw=1.2)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("count")
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)
    return [SHOWN_MAILLE, "run", path, "--no-frames"]


def with_plot(row, name, rel, shown_run):
    """The row with the plot of its stats.csv columns after the description."""
    cells = row.split(" | ")
    run = " ".join(shlex.quote(c) for c in shown_run)
    cells[2] += (f"<br>![{name} counts]({rel})<br>{', '.join(GALLERY_PLOTS[name])} over the "
                 f"whole run (`{run}`, stats.csv)")
    return " | ".join(cells)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--maille", required=True)
    p.add_argument("--examples", default="examples")
    p.add_argument("--out", required=True, help="directory for the PNG thumbnails")
    p.add_argument("--md", required=True, help="the gallery page to write")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--width", type=int)
    p.add_argument("--height", type=int)
    p.add_argument("--only", help="comma-separated scene names to render; the others' "
                   "thumbnails in --out are kept")
    a = p.parse_args()
    width = a.width or (160 if a.quick else 320)
    height = a.height or (90 if a.quick else 180)
    os.makedirs(a.out, exist_ok=True)
    md_dir = os.path.dirname(os.path.abspath(a.md))
    rows, failed, kept, started = [], [], [], time.monotonic()
    scenes = sorted(glob.glob(os.path.join(a.examples, "*.toml")))
    only = set(a.only.split(",")) if a.only else None
    if only:
        unknown = only - {os.path.splitext(os.path.basename(s))[0] for s in scenes}
        if unknown:
            print(f"gallery: --only: no such scene in {a.examples}: {', '.join(sorted(unknown))}",
                  file=sys.stderr)
            sys.exit(2)
    for path in scenes:
        name = os.path.splitext(os.path.basename(path))[0]
        with open(path, "rb") as f:
            scene = tomllib.load(f)
        description = scene.get("scene", {}).get("description", "")
        duration = scene.get("simulation", {}).get("duration", 2.0)
        t = QUICK_TIME.get(name, 0.1) if a.quick else GALLERY_TIME.get(name, min(duration, 2.0))
        png = os.path.join(a.out, name + ".png")
        cmd = [a.maille, "render", path, "--out", png, "--duration", f"{t:g}",
               "--width", str(width), "--height", str(height)]
        if name in GALLERY_CAMERA:
            cmd += ["--camera", GALLERY_CAMERA[name]]
        cmd += GALLERY_FLAGS.get(name, [])
        rel = os.path.relpath(png, md_dir)
        shown = " ".join(shlex.quote(c) for c in [SHOWN_MAILLE] + cmd[1:])
        row = f"| ![{name}]({rel}) | `{name}` | {description} (t = {t:g} s) | `{shown}` |"
        if only and name not in only:
            plot = os.path.join(a.out, name + "_counts.png")
            if name in GALLERY_PLOTS and os.path.exists(plot):
                row = with_plot(row, name, os.path.relpath(plot, md_dir),
                                [SHOWN_MAILLE, "run", path, "--no-frames"])
            if os.path.exists(png):
                kept.append(name)
                rows.append(row)
            else:
                failed.append(name)
                print(f"gallery: {name}: no thumbnail in {a.out} to keep (not in --only)",
                      file=sys.stderr)
            continue
        t0 = time.monotonic()
        r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        wall = time.monotonic() - t0
        if r.returncode != 0:
            failed.append(name)
            print(f"gallery: {name}: exit {r.returncode}: {r.stderr.strip()[-300:]}",
                  file=sys.stderr)
            continue
        size = os.path.getsize(png)
        print(f"gallery: {name:24s} t = {t:5.2f} s  {wall:6.1f} s wall  {size / 1e3:5.1f} kB")
        if name in GALLERY_PLOTS and not a.quick:
            plot = os.path.join(a.out, name + "_counts.png")
            shown_run = plot_counts(a.maille, path, name, GALLERY_PLOTS[name], plot)
            if shown_run is None:
                failed.append(name)
                continue
            row = with_plot(row, name, os.path.relpath(plot, md_dir), shown_run)
        rows.append(row)
    total = time.monotonic() - started
    page = [
        "# Gallery",
        "",
        "<!-- Generated by scripts/gallery.sh (scripts/report/gallery.py): do not edit. -->",
        "",
        f"Every scene in `examples/` ({len(scenes)}), rendered headless by `maille render` "
        f"({width} x {height}, the last frame at the time given; "
        + (f"{len(rows) - len(kept)} rendered in {total:.0f} s of wall time by this run, "
           f"{len(kept)} kept from an earlier one"
           if only else f"{len(rows)} rendered in {total:.0f} s of wall time")
        + f"{' in the quick mode' if a.quick else ''}). "
        "Each command reproduces its thumbnail; `--out NAME.mp4` instead makes a video "
        "(`--width 1280 --height 720` for a large one), `--camera YAW,PITCH,ZOOM` turns the "
        "view. Regenerate the page with `scripts/gallery.sh` (or `scripts/report.sh`, which "
        "runs it).",
        "",
        "| thumbnail | scene | what it shows | command |",
        "|---|---|---|---|",
    ] + rows
    if failed:
        page += ["", "Failed to render: " + ", ".join(f"`{n}`" for n in failed)]
    page += kept_timings(a.md)
    with open(a.md + ".tmp", "w") as f:
        f.write("\n".join(page) + "\n")
    os.replace(a.md + ".tmp", a.md)
    print(f"gallery: {len(rows)} of {len(scenes)} scenes ({len(kept)} kept) in {total:.0f} s -> "
          f"{a.md}")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
