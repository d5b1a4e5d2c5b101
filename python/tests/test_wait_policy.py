"""OpenMP's wait policy is chosen before the engine loads OpenMP (python/maille/__init__.py):
with a core kept busy by another program and no policy set, `import maille` sets
OMP_WAIT_POLICY=passive before libgomp reads it (else two threads spin against a descheduled
partner); a policy the user set is kept. What libgomp read is what it prints when
OMP_DISPLAY_ENV=verbose: GOMP_SPINCOUNT 0 when waiting is passive."""
import os
import subprocess
import sys
import time

import pytest

pytestmark = pytest.mark.skipif(
    len(os.sched_getaffinity(0)) < 2, reason="one core: never shared with a busy program"
)


def import_maille(**env_extra):
    """libgomp's GOMP_SPINCOUNT and OMP_WAIT_POLICY, and os.environ's policy, after `import maille`
    in a fresh interpreter with the environment less any policy, plus env_extra."""
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")}
    env.update(env_extra)
    env["OMP_DISPLAY_ENV"] = "verbose"
    code = "import os, maille; print(os.environ.get('OMP_WAIT_POLICY'))"
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    shown = {}
    for line in r.stderr.splitlines():
        if "=" in line:
            key, _, value = line.partition("=")
            shown[key.strip()] = value.strip().strip("'")
    assert "GOMP_SPINCOUNT" in shown, r.stderr  # libgomp displayed its settings
    return shown["GOMP_SPINCOUNT"], shown["OMP_WAIT_POLICY"], r.stdout.strip()


@pytest.fixture
def busy_core():
    spinner = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    time.sleep(0.5)
    yield
    spinner.kill()
    spinner.wait()


def test_busy_core_makes_waiting_passive(busy_core):
    spin, policy, environ = import_maille()
    assert spin == "0" and policy == "PASSIVE", (spin, policy)
    assert environ == "passive"  # the process's policy, as its children will see it


def test_the_users_policy_is_kept(busy_core):
    spin, policy, environ = import_maille(OMP_WAIT_POLICY="active")
    assert policy == "ACTIVE" and spin != "0", (spin, policy)
    assert environ == "active"
