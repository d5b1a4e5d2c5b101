#!/usr/bin/env bash
# The report pipeline, quick: `maille study all --quick` writes every CSV the report reads,
# each with its documented columns and plausible values (integrator orders near theory, the
# validity cases within their tolerances, leapfrog's limit at h omega = 2, ...), and
# scripts/report/report.py draws every figure and fills the whole template from that data, and
# (when `maille render` is built) every example renders for the quick gallery; the live section
# (scripts/bench_live.sh --quick) is measured and fills its table.
# It holds the checks of the former cli.study_csv_columns and cli.study_obstacles_tables, which
# ran the same quick studies on their own.
# Usage: cli_report_quick.sh MAILLE OUT SOURCE_DIR
set -u
maille=$1 out=$2 src=$3
rm -rf "$out"
mkdir -p "$out"
timeout 300 "$maille" study all --quick --out "$out/data" >"$out/study.log" 2>&1 ||
  { cat "$out/study.log"; echo "maille study all --quick failed"; exit 1; }
/usr/bin/python3 - "$out/data" <<'PY' || exit 1
import csv, math, os, sys
root = sys.argv[1]
# The documented columns (docs/report.md's "Data" section lists the same).
columns = {
    "durations.csv": "study,quick,wall_s",
    "validity/validity.csv": "case,quantity,analytic,measured,relative_error,tolerance",
    "integrators/stability.csv":
        "scheme,stiffness_N_per_m,mass_kg,damping_Ns_per_m,max_stable_step_s",
    "integrators/accuracy.csv": "scheme,step_s,error_at_1s_m",
    "integrators/energy.csv": "scheme,periods,steps_per_period,energy_ratio",
    "integrators/cost.csv":
        "scheme,points,threads,force_passes,ns_per_step,ns_per_particle_step,cg_iterations",
    "integrators/crossover.csv":
        "stiffness_N_per_m,scheme,step_s,leapfrog_limit_s,wall_s_per_simulated_s,sag_m,"
        "peak_stretch,reference_sag_m,reference_peak_stretch,comparable",
    "self-collision/scaling.csv":
        "side,particles,broad_phase,threads,ns_per_particle_pass,candidate_pairs,contacts,"
        "occupied_cells,cell_size_m",
    "self-collision/cell_size.csv":
        "broad_phase,side,cell_factor,cell_size_m,occupied_cells,particles_per_cell,"
        "model_P_n2,measured_ns,tuner_choice",
    "self-collision/tuner.csv":
        "broad_phase,side,cell_size_m,occupied_cells,model_P_n2,measured_ns,chosen",
    "self-collision/exclusion.csv":
        "exclusion,side,particles,candidate_pairs,excluded_pairs,skipped_cells,contacts,"
        "exclusion_bytes,ns_per_particle_pass,cell_size_m",
    "self-collision/memory.csv":
        "particles,exclusion,bytes,bytes_per_particle,dense_bit_matrix_bytes",
    "self-collision/flag_wind.csv": "scene,particles,self_collision,steps,ns_per_particle_step",
    "obstacles/obstacles.csv":
        "shape,method,particles,steps,max_penetration_m,mean_contacts,obstacle_ns_pps,"
        "link_ns_pps",
    "obstacles/incline.csv": "method,mu,theta_deg,seconds,distance_m,analytic_m,relative_error",
    "obstacles/lean.csv": "scale_x,scale_y,scale_z,mean_lean_deg,max_lean_deg",
    "large-steps/large_steps.csv":
        "scene,particles,solver,step_s,iterations,wall_s_per_sim_s,max_stretch,"
        "max_penetration_m,final_kinetic_J,max_residual,stable,sim_s,coarse,threads",
}
bad = []
tables = {}
for name, header in columns.items():
    path = os.path.join(root, name)
    if not os.path.exists(path):
        bad.append(f"{name}: missing")
        continue
    with open(path) as f:
        rows = list(csv.reader(f))
    if ",".join(rows[0]) != header:
        bad.append(f"{name}: header {','.join(rows[0])!r}, documented {header!r}")
    if len(rows) < 2:
        bad.append(f"{name}: no rows")
    for i, r in enumerate(rows[1:], 2):
        if len(r) != len(rows[0]):
            bad.append(f"{name}:{i}: {len(r)} fields, header has {len(rows[0])}")
    tables[name] = [dict(zip(rows[0], r)) for r in rows[1:]]

def check(what, ok):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        bad.append(what)

for r in tables.get("validity/validity.csv", []):
    check(f"validity {r['case']}: error {r['relative_error']} <= {r['tolerance']}",
          float(r["relative_error"]) <= float(r["tolerance"]))
acc = tables.get("integrators/accuracy.csv", [])
for scheme, order, slack in (("explicit_euler", 1, 0.3), ("symplectic_euler", 1, 0.3),
                             ("leapfrog", 2, 0.3), ("velocity_verlet", 2, 0.3),
                             ("rk4", 4, 0.6), ("implicit_euler", 1, 0.3)):
    pts = [(float(r["step_s"]), float(r["error_at_1s_m"])) for r in acc if r["scheme"] == scheme]
    pts = [(h, e) for h, e in pts if e > 1e-11]
    lx = [math.log(h) for h, _ in pts]
    ly = [math.log(e) for _, e in pts]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    slope = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)
    check(f"order of {scheme}: {slope:.2f}, theory {order}", abs(slope - order) <= slack)
for r in tables.get("integrators/stability.csv", []):
    if r["scheme"] == "leapfrog" and float(r["damping_Ns_per_m"]) == 0:
        hw = float(r["max_stable_step_s"]) * math.sqrt(float(r["stiffness_N_per_m"]) /
                                                       float(r["mass_kg"]))
        if abs(hw - 2) > 1e-3:
            check(f"leapfrog h* omega = {hw} at k = {r['stiffness_N_per_m']}", False)
energy = {r["scheme"]: float(r["energy_ratio"]) for r in tables.get("integrators/energy.csv", [])}
check(f"leapfrog energy ratio {energy.get('leapfrog')} within 1e-3 of 1",
      abs(energy.get("leapfrog", 0) - 1) < 1e-3)
check(f"explicit Euler gains energy ({energy.get('explicit_euler')})",
      energy.get("explicit_euler", 0) > 1)
check(f"implicit Euler loses energy ({energy.get('implicit_euler')})",
      energy.get("implicit_euler", 1) < 1)
for r in tables.get("integrators/cost.csv", []):
    check(f"cost {r['scheme']}: {r['ns_per_particle_step']} ns per particle-step > 0",
          float(r["ns_per_particle_step"]) > 0)
ex = {r["exclusion"]: r for r in tables.get("self-collision/exclusion.csv", [])}
check("matrix and signature leave the same contacts",
      ex and ex["matrix"]["contacts"] == ex["signature"]["contacts"])
check("the three exclusions share one cell size",
      ex and ex["none"]["cell_size_m"] == ex["matrix"]["cell_size_m"] == ex["signature"]["cell_size_m"])
check("signature uses less memory than the matrix",
      ex and int(ex["signature"]["exclusion_bytes"]) < int(ex["matrix"]["exclusion_bytes"]))
chosen = [r for r in tables.get("self-collision/cell_size.csv", []) if r["tuner_choice"] == "1"]
check(f"the tuner's choice is marked once per grid ({len(chosen)})", len(chosen) == 2)
# crossover.csv: leapfrog's limit in its own column on every row, implicit Euler's included
# (it once went to wall_s_per_simulated_s).
for i, r in enumerate(tables.get("integrators/crossover.csv", []), 2):
    if r["leapfrog_limit_s"] == "":
        check(f"crossover.csv:{i}: leapfrog_limit_s empty", False)
obstacles = tables.get("obstacles/obstacles.csv", [])
check(f"obstacles.csv: 9 shape x method rows ({len(obstacles)})", len(obstacles) == 9)
for r in obstacles:
    # The facets never let the cloth into the exact cube; the others stay within 1 cm.
    limit = 0 if r["method"] == "facets" and r["shape"] != "sphere" else 0.01
    check(f"{r['shape']} by {r['method']}: penetration {r['max_penetration_m']} m <= {limit}",
          0 <= float(r["max_penetration_m"]) <= limit)
for r in tables.get("obstacles/incline.csv", []):
    # The frictionless geometric and facet slides match the analytic distance within 1 %; the
    # conditional bead rides a sampled shell (bumps between samples): 10 %.
    limit = 0.1 if r["method"] == "conditional" else 0.01
    check(f"incline {r['method']} mu {r['mu']}: error {r['relative_error']} < {limit}",
          float(r["relative_error"]) < limit)
for r in tables.get("large-steps/large_steps.csv", []):
    # Every setting stays finite; leapfrog at its limit keeps the stretch under 10 % and the
    # penetration under 2 mm (the reference the implicit rows are read against).
    what = f"large steps {r['scene']} {r['solver']} h {r['step_s']}"
    check(f"{what}: stable", r["stable"] == "1")
    if r["solver"] == "leapfrog":
        check(f"{what}: stretch {r['max_stretch']} < 0.1, penetration {r['max_penetration_m']} "
              f"< 0.002", float(r["max_stretch"]) < 0.1 and float(r["max_penetration_m"]) < 2e-3)
if bad:
    print("\n".join(["", "problems:"] + bad))
    sys.exit(1)
PY
if ! /usr/bin/python3 -c 'import matplotlib' 2>/dev/null; then
  echo "matplotlib missing (scripts/setup.sh python3-matplotlib): figures not checked"
  exit 77
fi
# The live section's data (scripts/bench_live.sh --quick: six short `maille play --benchmark`).
mkdir -p "$out/data/live"
timeout 120 "$src/scripts/bench_live.sh" --maille "$maille" --quick --out "$out/data/live/live.csv" ||
  { echo "scripts/bench_live.sh --quick failed"; exit 1; }
[ "$(grep -c ',ok$' "$out/data/live/live.csv")" = 6 ] ||
  { cat "$out/data/live/live.csv"; echo "live.csv: 6 rows measured without a blow-up expected"; exit 1; }
/usr/bin/python3 "$src/scripts/report/report.py" --data "$out/data" --figures "$out/figures" \
  --template "$src/scripts/report/report.md.in" --md "$out/report.md" || exit 1
grep -q '^| square drum' "$out/report.md" || { echo "report.md: no live table"; exit 1; }
for f in $(/usr/bin/python3 -c "import sys; sys.path.insert(0, '$src/scripts/report'); import report; print(' '.join(report.FIGURES))"); do
  [ -s "$out/figures/$f" ] || { echo "figure $f not written"; exit 1; }
done
if grep -n '{{' "$out/report.md"; then echo "report.md: unfilled keys"; exit 1; fi
# `maille render --help` exits 0 even without rendering (CLI11 prints the main help before it
# refuses the unknown command): the render command's own option tells.
if "$maille" render --help 2>&1 | grep -q -- '--fps'; then
  /usr/bin/python3 "$src/scripts/report/gallery.py" --maille "$maille" --examples "$src/examples" \
    --out "$out/gallery" --md "$out/gallery.md" --quick >"$out/gallery.log" 2>&1 ||
    { cat "$out/gallery.log"; echo "gallery: a scene failed to render"; exit 1; }
  n=$(ls "$src"/examples/*.toml | wc -l)
  [ "$(ls "$out"/gallery/*.png | wc -l)" -eq "$n" ] || { echo "gallery: not $n thumbnails"; exit 1; }
else
  echo "rendering is not built (maille render): the quick gallery is skipped"
fi
echo "every CSV, figure and value of the quick report: $out"
