"""Shared by the module's tests: where the repository, its scenes and the command line are.

ctest runs each file with PYTHONPATH pointing at the built module and MAILLE_EXE at the
`maille` command line of the same build (python/CMakeLists.txt)."""
import os
import pathlib
import shutil
import threading

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
DATA = ROOT / "tests" / "data"
FLAG = EXAMPLES / "flag_in_wind.toml"
CHAIN = EXAMPLES / "pendulum_chain.toml"
UNSTABLE = DATA / "unstable_spring.toml"


def step_from_another_thread(sim, before=None):
    """Starts a thread that calls sim.step(1), after before() when given; returns the thread and
    the list that collects the messages of the RuntimeErrors it raised (read it after join())."""
    errors = []

    def other():
        if before:
            before()
        try:
            sim.step(1)
        except RuntimeError as e:
            errors.append(str(e))

    t = threading.Thread(target=other)
    t.start()
    return t, errors


def maille_exe():
    exe = os.environ.get("MAILLE_EXE")
    if exe:
        return exe
    for preset in ("dev", "release"):
        candidate = ROOT / "build" / preset / "apps" / "maille" / "maille"
        if candidate.exists():
            return str(candidate)
    return shutil.which("maille")


@pytest.fixture
def exe():
    path = maille_exe()
    if not path:
        pytest.skip("the maille command line is not built")
    return path
