"""What a hostile or careless user can pass must never end the interpreter: every case that
once crashed (a signal), aborted or hung runs in a subprocess, so that a regression fails this
test instead of killing the test run. Each test names the defect it pins."""
import os
import pathlib
import signal
import stat
import subprocess
import sys
import textwrap
import threading
import time
import warnings

import numpy as np
import pytest

import maille
from conftest import EXAMPLES, FLAG

HERE = pathlib.Path(__file__).resolve().parent  # conftest.py, for the scripts run apart
SPHERE = EXAMPLES / "cloth_on_sphere.toml"  # self-collision (particle-face) and obstacles


def run_python(code, timeout=120, env=None):
    """Runs `code` in a fresh interpreter with this one's module path; returns the process."""
    full_env = dict(os.environ)
    full_env.update(env or {})
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, timeout=timeout, env=full_env)


def assert_clean(proc, *expected):
    """No signal, exit 0, and each expected text in stdout."""
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    for text in expected:
        assert text in proc.stdout, proc.stdout + proc.stderr


# --- 2. a non-finite position never reaches a stage's grid ------------------------------------


def test_non_finite_position_written_from_python_is_a_blow_up():
    proc = run_python(f"""
        import math, maille
        sim = maille.Simulation({str(SPHERE)!r})
        sim.step(2)
        before = sim.state_hash()
        for value in (math.inf, -math.inf, math.nan):
            sim.positions[100, 1] = value
            try:
                sim.step(1)
            except maille.BlowUp as e:
                assert "point 100" in str(e), str(e)
                assert e.step == 2, e.step
            else:
                raise SystemExit("no BlowUp for " + repr(value))
            assert sim.steps == 2
        print("raised")
    """)
    assert_clean(proc, "raised")


def test_checkpoint_holding_a_non_finite_state_is_a_blow_up(tmp_path):
    proc = run_python(f"""
        import math, maille
        sim = maille.Simulation({str(SPHERE)!r})
        sim.step(1)
        sim.velocities[7, 0] = math.nan
        sim.save_checkpoint({str(tmp_path / "nan.bin")!r})
        fresh = maille.Simulation({str(SPHERE)!r})
        fresh.load_checkpoint({str(tmp_path / "nan.bin")!r})
        try:
            fresh.step(1)
        except maille.BlowUp as e:
            assert "point 7" in str(e), str(e)
            print("raised")
    """)
    assert_clean(proc, "raised")


# --- 3. values that contain themselves or nest without end ------------------------------------


def test_self_referencing_and_deep_values_are_scene_errors():
    proc = run_python(f"""
        import maille
        loop = [1.0]
        loop.append(loop)
        table = {{}}
        table["a"] = table
        deep = 0.0
        for _ in range(100000):
            deep = [deep]
        doubling = [0.0]
        for _ in range(40):
            doubling = [doubling, doubling]
        sim = maille.Simulation({str(FLAG)!r})
        model = maille.Model()
        calls = [
            lambda v: maille.Simulation({str(FLAG)!r}, overrides={{"fields.gravity": v}}),
            lambda v: sim.set("fields.gravity", v),
            lambda v: model.set("fields.gravity", v),
            lambda v: model.add_flag(origin=v),
        ]
        for value in (loop, table, deep, doubling):
            for call in calls:
                try:
                    call(value)
                except maille.SceneError as e:
                    assert e.key, e
                else:
                    raise SystemExit("accepted")
        print("refused")
    """)
    assert_clean(proc, "refused")


# --- 4. multiprocessing's fork after the parent ran threads -----------------------------------


def test_fork_children_step_after_the_parent_ran_two_threads():
    proc = run_python(f"""
        import multiprocessing as mp, maille

        def work(steps):
            sim = maille.Simulation({str(FLAG)!r}, threads=2)
            sim.step(steps)
            return sim.threads, sim.state_hash()

        if __name__ == "__main__":
            parent = maille.Simulation({str(FLAG)!r}, threads=2)
            parent.step(50)  # libgomp's team now exists in this process only
            reference = maille.Simulation({str(FLAG)!r}, threads=1)
            reference.step(50)
            ctx = mp.get_context("fork")
            with ctx.Pool(2) as pool:
                results = pool.map(work, [50, 50])
            for threads, digest in results:
                assert threads == 1, threads
                assert digest == reference.state_hash()
            # The parent's own simulation goes on with its threads.
            parent.step(10)
            print("children done", parent.threads)
    """, timeout=120)
    assert_clean(proc, "children done 2")


# --- 5. a daemon thread stepping while the interpreter exits -----------------------------------


def test_daemon_thread_stepping_at_exit_exits_cleanly():
    proc = run_python(f"""
        import threading, time, maille
        sim = maille.Simulation({str(FLAG)!r})
        def forever():
            while True:
                sim.step(100)
        threading.Thread(target=forever, daemon=True).start()
        time.sleep(0.3)
        print("leaving")
    """)
    assert_clean(proc, "leaving")
    assert "terminate" not in proc.stderr


# --- 6. Ctrl-C inside a step that would last minutes ------------------------------------------


@pytest.mark.parametrize("solver", [
    {"simulation.implicit.solver": "vbd", "simulation.implicit.iterations": 100000},
    {"simulation.implicit.solver": "matrix_free", "simulation.implicit.newton_iterations": 100,
     "simulation.implicit.max_iterations": 1048576, "simulation.implicit.tolerance": 1e-300},
])
def test_ctrl_c_stops_inside_a_long_implicit_step(solver):
    sim = maille.Simulation(SPHERE, {"simulation.integrator": "implicit_euler",
                                     "simulation.step": 0.1})
    sim.step(3)  # onto the sphere: Newton's iterations no longer end at once (free fall)
    for key, value in solver.items():  # now each step would last minutes
        sim.set(key, value)
    before = sim.state_hash()
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.step(1)  # minutes if it ran to its end
    finally:
        timer.cancel()
    assert sim.steps == 3 and sim.state_hash() == before  # the last whole step's state


# --- 7. set() costs its own key, not every earlier edit ---------------------------------------


def test_repeated_set_keeps_one_override_per_key():
    sim = maille.Simulation(FLAG)
    for k in range(300):
        sim.set("fields.wind.velocity", [float(k % 7), 0.0, 1.0])
        sim.set("flag[0].stiffness", 300.0 + k)
    assert len(sim.overrides) == 2  # what each set re-reads: the keys, not the edits
    assert sim.overrides[-1] == "flag[0].stiffness=599"
    fresh = maille.Simulation(FLAG, {"fields.wind.velocity": [5.0, 0.0, 1.0],  # 299 % 7
                                     "flag[0].stiffness": 599})
    sim.reset()
    fresh.step(20)
    sim.step(20)
    assert sim.state_hash() == fresh.state_hash()


# --- 8. every reader takes the busy guard -----------------------------------------------------


def test_readers_while_another_thread_steps_never_tear():
    proc = run_python(f"""
        import threading, maille
        sim = maille.Simulation({str(FLAG)!r}, overrides={{"simulation.sample_every": 1}})
        done = threading.Event()
        def stepper():
            for _ in range(200):
                try:
                    sim.step(20)
                except RuntimeError:
                    pass
            done.set()
        threading.Thread(target=stepper).start()
        refused = complete = 0
        readers = [sim.stats, sim.energies, sim.state_hash, lambda: sim.time,
                   lambda: sim.positions, lambda: sim.groups, repr]
        while not done.is_set():
            for read in readers:
                try:
                    value = read(sim) if read is repr else read()
                except RuntimeError as e:
                    assert "busy" in str(e)
                    refused += 1
                else:
                    if read == sim.stats and value:
                        assert value["step"] % 1 == 0 and "total" in value
                    complete += 1
        print("ok", refused > 0 or complete > 0)
    """)
    assert_clean(proc, "ok True")


# --- 10. an implicit step that does not converge is said ---------------------------------------


def test_unconverged_implicit_steps_warn_once():
    sim = maille.Simulation(SPHERE, {"simulation.integrator": "implicit_euler",
                                     "simulation.implicit.solver": "matrix_free",
                                     "simulation.step": 0.1})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sim.step(8)  # unconverged from step 3, five in a row by step 7
        sim.step(1)
    unconverged = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(unconverged) == 1, [str(w.message) for w in caught]
    text = str(unconverged[0].message)
    assert "matrix_free" in text and "unconverged, the first at step" in text


# --- 12. a blow-up is raised before control returns ---------------------------------------


def test_a_runaway_under_an_implicit_scheme_is_raised_by_the_call_that_made_it():
    # A finite but absurd position (1e200 m) under VBD: the energies overflow within the call;
    # sampled only every 10,000 steps, the runaway must still be raised by this step().
    sim = maille.Simulation(SPHERE, {"simulation.integrator": "implicit_euler",
                                     "simulation.step": 1 / 60,
                                     "simulation.sample_every": 10000})
    sim.step(1)
    sim.positions[5] = [1e200, 0.0, 0.0]
    with pytest.raises(maille.BlowUp):
        sim.step(3)
    with pytest.raises(maille.BlowUp):  # and again, until reset()
        sim.step(1)
    sim.reset()
    sim.step(1)


# --- 13. a GPU simulation belongs to its thread -----------------------------------------------


def test_gpu_simulation_called_from_another_thread_is_refused():
    if not maille.render_available:
        pytest.skip("built without rendering (no GPU backend)")
    proc = run_python(f"""
        import sys, maille
        sys.path.insert(0, {str(HERE)!r})
        from conftest import step_from_another_thread
        sim = maille.Simulation({str(FLAG)!r}, overrides={{"simulation.backend": "gpu"}})
        sim.step(2)
        t, errors = step_from_another_thread(sim)
        t.join()
        assert errors and "thread that created" in errors[0], errors
        sim.step(2)  # its own thread still steps
        print("refused", sim.steps)
    """, env={"MAILLE_GPU_LAYOUT": "auto"})
    if "cannot" in proc.stderr and proc.returncode != 0 and "EGL" in proc.stderr:
        pytest.skip("no OpenGL 4.5 context here")
    assert_clean(proc, "refused 4")


# --- 14. the smaller ones ---------------------------------------------------------------------


def test_wrong_argument_types_name_the_argument():
    sim = maille.Simulation(FLAG)
    cases = [
        (lambda: sim.step("10"), "'n'"),
        (lambda: sim.step(2.5), "'n'"),
        (lambda: sim.run(steps="x"), "'steps'"),
        (lambda: sim.run(duration="x"), "'duration'"),
        (lambda: sim.run(steps=2, callback=3), "'callback'"),
        (lambda: sim.set(3, 1.0), "'key'"),
        (lambda: sim.save_checkpoint(12), "'path'"),
        (lambda: maille.Simulation(FLAG, threads="two"), "'threads'"),
        (lambda: maille.Simulation(FLAG, step="fast"), "'step'"),
        (lambda: maille.Simulation(3.0), "'source'"),
        (lambda: maille.Model().add_point([0, 0, 0], mass="heavy"), "'mass'"),
        (lambda: maille.Model().add_point("abc"), "'position'"),
        (lambda: maille.Model().add_link(5, 0, 1), "'kind'"),
    ]
    for call, name in cases:
        with pytest.raises((TypeError, maille.SceneError)) as e:
            call()
        assert name in str(e.value) or getattr(e.value, "key", "") == name.strip("'"), str(e.value)


def test_checkpoint_paths_take_pathlib_and_refuse_nul(tmp_path):
    sim = maille.Simulation(FLAG)
    sim.step(3)
    sim.save_checkpoint(tmp_path / "a.bin")  # a pathlib.Path
    sim.load_checkpoint(tmp_path / "a.bin")
    for path in (str(tmp_path / "a\0b.bin"), ""):
        with pytest.raises(maille.SceneError) as e:
            sim.save_checkpoint(path)
        assert e.value.key == "path"
    with pytest.raises(maille.SceneError):
        maille.Simulation(str(FLAG) + "\0.toml")
    assert not (tmp_path / "a").exists()


def test_keys_cannot_inject_toml():
    model = maille.Model()
    with pytest.raises(maille.SceneError):
        model.add_flag(**{"resolution = [2, 2]\nmass": 1.0})
    with pytest.raises(maille.SceneError):
        maille.Simulation(FLAG, overrides={"fields.gravity=[0,0,0]\n[x]\ny": 1})
    with pytest.raises(maille.SceneError):
        maille.Simulation(FLAG, overrides=["fields.gravity=[0, 0, 0]\nflag[0].mass=3"])
    assert model.point_count == 0


def test_pair_cap_is_a_maille_error():
    # A memory budget that the self-collision pairs of a crumpled cloth exceed at once.
    proc = run_python(f"""
        import maille
        sim = maille.Simulation({str(EXAMPLES / "cloth_heap.toml")!r},
                                {{"self_collision.radius": 0.2}})
        try:
            sim.step(1)
        except maille.Error as e:
            print("refused", type(e).__name__, "contact pairs" in str(e))
    """, env={"MAILLE_MEMORY_BUDGET": "2000000"})
    assert_clean(proc, "refused SceneError True")


def test_model_out_of_memory_leaves_no_half_flag():
    proc = run_python("""
        import resource, maille
        model = maille.Model()
        model.add_flag(resolution=[20, 20])
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        resource.setrlimit(resource.RLIMIT_AS, (1 << 30, hard))
        raised = None
        for k in range(400):
            try:
                model.add_flag(name=f"f{k}", resolution=[300, 300])
            except (MemoryError, maille.SceneError) as e:
                raised = type(e).__name__
                break
        groups = sum(len(v) for v in model.groups.values())
        assert groups == model.point_count, (groups, model.point_count)
        print("consistent", raised)
    """, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "consistent" in proc.stdout


def test_many_threads_under_a_memory_limit_raise():
    proc = run_python(f"""
        import resource, maille
        resource.setrlimit(resource.RLIMIT_AS, (1 << 31, resource.RLIM_INFINITY))
        try:
            sim = maille.Simulation({str(FLAG)!r}, threads=1024)
            sim.step(2)
        except maille.SceneError as e:
            print("refused", "threads" in str(e))
        else:
            print("ran")
    """)
    assert proc.returncode == 0, proc.stderr
    assert "refused True" in proc.stdout or "ran" in proc.stdout


def test_keys_a_solver_ignores_are_said():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        maille.Simulation(FLAG, {"simulation.integrator": "implicit_euler",
                                 "simulation.implicit.solver": "vbd",
                                 "simulation.implicit.tolerance": 1e-9})
    texts = [str(w.message) for w in caught]
    assert any("tolerance" in t and "vbd" in t for t in texts), texts


def test_a_denormal_radius_does_not_hang_the_broad_phase():
    # Found by the boundary fuzz: self_collision.radius = 5e-324 is a positive number, and the
    # grids grew their cell by 1.25 from it, which rounds back to 5e-324 for ever.
    proc = run_python(f"""
        import maille
        for primitive in ("points", "triangles"):
            sim = maille.Simulation({str(SPHERE)!r}, {{"self_collision.radius": 5e-324,
                                    "self_collision.primitive": primitive}})
            sim.energies()
            sim.step(2)
        print("stepped")
    """, timeout=120)
    assert_clean(proc, "stepped")


# --- 1. outputs never replace a FIFO or a device ----------------------------------------------


def test_checkpoint_into_a_fifo_keeps_the_fifo(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received = []
    reader = threading.Thread(target=lambda: received.append(pathlib.Path(fifo).read_bytes()))
    reader.start()
    sim = maille.Simulation(FLAG)
    sim.step(3)
    sim.save_checkpoint(fifo)
    reader.join(timeout=30)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert received and len(received[0]) > 1000
    assert not (tmp_path / "pipe.tmp").exists()


def test_checkpoint_into_dev_null_keeps_the_device():
    before = os.stat("/dev/null")
    sim = maille.Simulation(FLAG)
    sim.save_checkpoint("/dev/null")
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and after.st_rdev == before.st_rdev


def test_render_into_a_symbolic_link_keeps_the_link(tmp_path):
    if not maille.render_available:
        pytest.skip("built without rendering")
    target = tmp_path / "real.png"
    target.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(target)
    sim = maille.Simulation(FLAG)
    sim.render(link, width=64, height=48, samples=1)
    assert link.is_symlink()
    assert target.read_bytes()[:4] == b"\x89PNG"
