"""`pip install --no-build-isolation .` from the checkout (pyproject.toml, setup.py) into a fresh
virtual environment that sees the system's packages, as docs/python.md says, then the package
analyses the sample from there.

A cold pip build compiles the libraries (minutes, docs/python.md states the measured time), so
this test hands setup.py the tests' own build (BOUNCECAL_PIP_BUILD_DIR), whose extension is
already built: it checks the packaging, not the compiler, in about 20 s. Nothing is downloaded
(--no-index)."""

import json
import os
import pathlib
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR, STEEL_SAMPLE

CHECK = """
import importlib.metadata, inspect, json, pathlib, sys
import bouncecal
package = pathlib.Path(bouncecal.__file__).parent
sequence = bouncecal.analyze(sys.argv[1], drop_height_m=0.2).sequences[0]
print(json.dumps({
    "file": bouncecal.__file__,
    "version": bouncecal.__version__,
    "distribution_version": importlib.metadata.version("bouncecal"),
    "stubs": sorted(p.name for p in package.iterdir() if p.suffix in (".pyi", ".typed")),
    "signature": str(inspect.signature(bouncecal.analyze)).startswith("(recording, *, drop_"),
    "eta_bar": sequence.energy_loss_mean_first_n,
}))
"""


def test_pip_installs_the_package_into_a_venv_that_then_analyzes_the_sample(tmp_path):
    build = os.environ.get("BOUNCECAL_BUILD_DIR")
    if not build:
        pytest.skip("BOUNCECAL_BUILD_DIR (the CMake build) is not set; run through ctest")
    venv = tmp_path / "venv"
    created = subprocess.run(
        [sys.executable, "-m", "venv", "--system-site-packages", str(venv)],
        capture_output=True, text=True)
    if created.returncode != 0:
        pytest.skip(f"no venv with pip for {sys.executable} (Debian: python3-venv): "
                    f"{created.stderr.strip()[-200:]}")
    python = venv / "bin" / "python"
    # Only the venv: not the build tree's package the other tests import.
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    env["BOUNCECAL_PIP_BUILD_DIR"] = build
    installed = subprocess.run(
        [str(python), "-m", "pip", "install", "--no-build-isolation", "--no-index",
         str(SOURCE_DIR)], capture_output=True, text=True, env=env, cwd=tmp_path, timeout=600)
    assert installed.returncode == 0, installed.stdout[-2000:] + installed.stderr[-2000:]

    env.pop("BOUNCECAL_PIP_BUILD_DIR")
    ran = subprocess.run([str(python), "-c", CHECK, str(STEEL_SAMPLE)], capture_output=True,
                         text=True, env=env, cwd=tmp_path, timeout=120)
    assert ran.returncode == 0, ran.stderr
    found = json.loads(ran.stdout)
    assert pathlib.Path(found["file"]).is_relative_to(venv)
    assert found["version"] == found["distribution_version"]
    assert found["stubs"] == ["__init__.pyi", "py.typed"]
    assert found["signature"]
    # The sample's eta-bar as the other install tests check it (tests/consumer/): it was
    # synthesised with 0.58, and its onsets give it to better than 0.005.
    assert abs(found["eta_bar"] - 0.58) < 0.005
