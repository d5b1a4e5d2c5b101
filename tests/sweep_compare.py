"""sweep_compare.py A.csv B.csv: two sweep summaries are the same, row by row and column by
column, but for what depends on the run and not on the case: wall_seconds, rank, and the stats'
per-stage timings (ns_*). Prints the first difference and exits 1 when they differ."""
import csv
import sys


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no rows")
    keep = [k for k in rows[0] if k not in ("wall_seconds", "rank") and not k.startswith("ns_")]
    return keep, [[r[k] for k in keep] for r in rows]


a_cols, a = load(sys.argv[1])
b_cols, b = load(sys.argv[2])
if a_cols != b_cols:
    sys.exit(f"columns differ:\n  {a_cols}\n  {b_cols}")
if len(a) != len(b):
    sys.exit(f"{len(a)} rows against {len(b)}")
for ra, rb in zip(a, b):
    for col, va, vb in zip(a_cols, ra, rb):
        if va != vb:
            sys.exit(f"case {ra[0]}, column {col}: {va!r} against {vb!r}")
print(f"{len(a)} rows, {len(a_cols)} columns identical (wall_seconds, rank, ns_* left out)")
