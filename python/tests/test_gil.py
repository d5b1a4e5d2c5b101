"""The GIL is released while stepping (another Python thread runs), taken back for callbacks,
and Ctrl-C interrupts a long step() between two steps."""
import os
import signal
import threading
import time

import pytest

import maille
from conftest import FLAG, step_from_another_thread


def test_a_python_thread_runs_while_step_runs():
    sim = maille.Simulation(FLAG, threads=1)
    sim.step(10)
    count = 0
    stop = threading.Event()

    def spin():
        nonlocal count
        while not stop.is_set():
            count += 1

    t = threading.Thread(target=spin)
    t.start()
    time.sleep(0.05)
    try:
        t0 = time.perf_counter()
        before = count
        sim.step(3000)  # about 0.2 s or more on the development machine
        during = count - before
        wall = time.perf_counter() - t0
    finally:
        stop.set()
        t.join()
    # With the GIL held for the whole call, the counter could not move while it runs.
    assert wall > 0.02
    assert during > 1000, f"the other thread counted {during} in {wall:.3f} s"


def test_callbacks_run_with_the_gil():
    sim = maille.Simulation(FLAG)
    times = []
    sim.run(steps=100, every=25, callback=lambda s: times.append(s.positions[0, 0] + s.time))
    assert len(times) == 4


def test_another_thread_cannot_step_at_the_same_time():
    sim = maille.Simulation(FLAG, threads=1)
    started = threading.Event()
    t, errors = step_from_another_thread(sim, before=lambda: (started.wait(), time.sleep(0.01)))
    started.set()
    sim.step(3000)
    t.join()
    assert errors and "busy" in errors[0]


def test_ctrl_c_interrupts_a_long_step():
    sim = maille.Simulation(FLAG, threads=1)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.step(10**9)  # hours if it ran to its end: stopping at all is the proof
    timer.join()
    steps = sim.steps
    assert 0 < steps < 10**9
    sim.step(5)  # still usable, at a whole step
    assert sim.steps == steps + 5
