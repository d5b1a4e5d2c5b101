"""Random values of every type into every argument of maille.Simulation, maille.Model and their
methods: the Python boundary's fuzz target (test_boundary_fuzz.py runs it in subprocesses).

    python3 fuzz_boundary.py SCENE WORKDIR FIRST_SEED COUNT

For each seed, one call with arguments drawn from a pool of hostile values (wrong types, NaN,
infinities, huge integers, NUL and newlines in strings, self-referencing containers, NumPy
arrays of every shape and dtype, paths). The outcome must be a return or one of the allowed
exceptions (maille.Error, TypeError, ValueError; OSError for a path that cannot be written
or read) with a message; anything
else is printed as "BAD <seed> ..." and the exit code is 1. A crash (a signal) is the parent's to
see: the last "SEED <n>" line written before it names the case. Values are chosen so that every
valid call stays cheap (no count of steps or points large enough to run long).
"""
import math
import os
import pathlib
import random
import sys

import numpy as np

import maille


def hostile_values(workdir):
    loop = [1.0]
    loop.append(loop)
    table = {}
    table["self"] = table
    deep = 0.0
    for _ in range(200):
        deep = [deep]
    return [
        None, True, False, 0, 1, 2, 3, -1, 7, 2**31, 2**63, -2**63 - 1, 2**100,
        0.0, -0.0, 1e-3, 0.25, 1.5, -2.5, 1e308, -1e308, 5e-324, math.nan, math.inf, -math.inf,
        "", "x", "flag", "spring_damper", "fields.gravity", "simulation.step", "a\0b", "a\nb",
        "a=b", "flag[0].stiffness", "\udcff", "é" * 3, "0", "[1, 2]", "simulation",
        b"bytes", bytearray(b"ab"), 1j, object(), print, lambda *a: None, type,
        [], [1.0, 2.0, 3.0], [0, 0, 0], [1, 2], ["a", "b", "c"], [math.nan, 0, 0], (1.0, 2.0, 3.0),
        [[1.0, 2.0, 3.0]], loop, table, deep, {}, {"a": 1}, {1: 2}, {"speed": math.inf},
        {"fields.gravity": [0, 0, 0]}, {"simulation.step": "fast"}, {"fields.gravity": loop},
        ["simulation.step=1e-4"], ["nonsense"], ["a=b\nc=d"], [1, 2, 3],
        np.float64(0.5), np.int64(3), np.bool_(True), np.array(2.0), np.zeros(3), np.ones((2, 3)),
        np.array([1, 2, 3], dtype=np.uint8), np.array(["a", "b"]), np.empty((0,)),
        np.array([np.nan, np.inf, 1.0]), np.zeros((3,), dtype=np.complex128),
        np.zeros((2, 2, 2)), pathlib.Path(workdir) / "f.bin", pathlib.Path(""),
        pathlib.Path(workdir), os.devnull, str(pathlib.Path(workdir) / "sub" / "x.bin"),
        range(3), iter([1, 2]), frozenset([1]), slice(1), Ellipsis,
    ]


def draw(rng, pool, k):
    return [rng.choice(pool) for _ in range(k)]


KEYWORDS = ["overrides", "threads", "step", "integrator", "n", "duration", "steps", "every",
            "callback", "key", "value", "path", "width", "height", "camera", "samples", "mesh",
            "position", "mass", "velocity", "name", "kind", "a", "b", "stiffness", "damping",
            "rest_length", "builder", "resolution", "origin", "fixed", "width_", "bogus"]


def call(rng, pool, scene, sims, models):
    """One random call; returns (label, argument names) for the message check."""
    sim = sims[0]
    model = models[0]
    small = [v for v in pool if not isinstance(v, (int, float)) or isinstance(v, bool)
             or (isinstance(v, (int, float)) and abs(v) < 100)]
    choice = rng.randrange(22)
    args = draw(rng, pool, 4)
    kwargs = {}
    if rng.random() < 0.3:
        kwargs = {rng.choice(KEYWORDS): rng.choice(pool) for _ in range(rng.randrange(1, 3))}
    if choice == 0:
        src = rng.choice([scene, scene, models[0]] + pool)
        sims.append(maille.Simulation(src, *args[:1], **kwargs))
    elif choice == 1:
        sim.step(rng.choice([v for v in small if not (isinstance(v, int) and v > 20)]))
    elif choice == 2:
        safe = {k: v for k, v in kwargs.items()
                if not (isinstance(v, (int, float)) and not isinstance(v, bool) and v > 2)}
        sim.run(rng.choice([None, math.nan, math.inf, -1.0, 1e308, "x", [1], 0.001]), **safe)
    elif choice == 3:
        sim.set(rng.choice(pool), rng.choice(pool))
    elif choice == 4:
        sim.set(rng.choice(["fields.gravity", "fields.air_drag", "simulation.step",
                            "simulation.integrator", "self_collision.radius",
                            "flag[0].stiffness", "fields.wind.velocity"]), rng.choice(pool))
    elif choice == 5:
        sim.save_checkpoint(rng.choice(pool))
    elif choice == 6:
        sim.load_checkpoint(rng.choice(pool))
    elif choice == 7:
        if maille.render_available:
            sim.render(rng.choice(pool), width=rng.choice([None, "x", 0, -1, 2**63, 1.5, 8]),
                       height=8, samples=rng.choice([1, 0, "a", None]))
    elif choice == 8:
        sim.energies(*args[:rng.randrange(2)])
    elif choice == 9:
        sim.stats(*args[:rng.randrange(2)])
    elif choice == 10:
        sim.state_hash()
        sim.reset()
    elif choice == 11:
        # NumPy's own checks answer for the view; what is written must not crash a step.
        sim.positions[rng.choice([0, 1, -1])] = rng.choice(
            [math.nan, math.inf, -math.inf, 1e308, 0.0, 2.0, np.array([math.nan, 1.0, 2.0])])
        sim.step(1)
    elif choice == 12:
        model.add_point(*args[:rng.randrange(1, 5)], **kwargs)
    elif choice == 13:
        model.add_fixed_point(*args[:rng.randrange(1, 4)], **kwargs)
    elif choice == 14:
        model.add_link(*args[:3], **kwargs)
    elif choice == 15:
        model.add_link("spring_damper", rng.choice(pool), rng.choice(pool),
                       **{rng.choice(["stiffness", "damping", "rest_length", "bogus"]):
                          rng.choice(pool)})
    elif choice == 16:
        keys = {rng.choice(["resolution", "origin", "mass", "stiffness", "width", "fixed",
                            "name\nx", "a=b", "along"]): rng.choice(pool)
                for _ in range(rng.randrange(1, 3))}
        if isinstance(keys.get("resolution"), int) and keys["resolution"] > 50:
            keys["resolution"] = [2**40, 2]
        model.add_flag(**keys)
    elif choice == 17:
        model.build(rng.choice(pool + ["rope", "net", "flag"]), **kwargs)
    elif choice == 18:
        model.set(rng.choice(pool), rng.choice(pool))
    elif choice == 19:
        models.append(maille.Model(*args[:rng.randrange(2)]))
    elif choice == 20:
        sims.append(maille.Simulation(scene, overrides=rng.choice(pool)))
    else:
        getattr(sim, rng.choice(["time", "steps", "groups", "masses", "fixed", "overrides",
                                 "velocities", "stable_step", "name"]))
        repr(sim)


def main():
    scene, workdir, first, count = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    os.chdir(workdir)  # whatever a path writes, it writes here
    pool = hostile_values(workdir)
    sims = [maille.Simulation(scene)]
    models = [maille.Model()]
    models[0].add_flag(name="cloth", resolution=[4, 4])
    bad = 0
    log = open(os.path.join(workdir, "last_seed"), "w")
    for seed in range(first, first + count):
        log.seek(0)
        log.write(f"SEED {seed}\n")
        log.flush()
        rng = random.Random(seed)
        try:
            call(rng, pool, scene, sims, models)
        except (maille.Error, TypeError, ValueError, OSError) as e:
            # OSError: a path that cannot be written or read (a directory, a missing folder),
            # as Python's own open() answers; documented in docs/python.md.
            if not str(e):
                print(f"BAD {seed}: {type(e).__name__} without a message")
                bad += 1
        except Exception as e:  # noqa: BLE001  (the point: anything else is a finding)
            print(f"BAD {seed}: {type(e).__name__}: {e}")
            bad += 1
        # Keep the pools small: long-lived simulations and models are not the point.
        del sims[4:]
        del models[4:]
        if sims[0].steps > 2000 or not np.all(np.isfinite(sims[0].positions)):
            sims[0] = maille.Simulation(scene)
    print(f"done {count} cases, {bad} bad")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
