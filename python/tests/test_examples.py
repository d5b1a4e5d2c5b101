"""The examples in examples/python/ run (their --quick variants)."""
import os
import pathlib
import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = ["parameter_scan", "cloth_callback", "model_in_code"]
OUTPUTS = {"parameter_scan": ["scan.png", "scan.csv"], "cloth_callback": ["corner.csv"],
           "model_in_code": ["oscillator.png"]}


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_runs(name, tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    r = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / f"{name}.py"),
                        "--quick", "--out", str(tmp_path)],
                       env=env, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    for f in OUTPUTS[name]:
        assert (pathlib.Path(tmp_path) / f).stat().st_size > 0
    if name == "model_in_code":
        assert "relative difference" in r.stdout
