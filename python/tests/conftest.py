"""Shared fixtures of the module's tests. ctest (python/CMakeLists.txt, test python_tests) runs
them on the module of the build tree with BOUNCECAL_SOURCE_DIR and BOUNCECAL_EXECUTABLE (the
command line, which several tests compare the module with) set."""

import json
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(
    os.environ.get("BOUNCECAL_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
STEEL_SAMPLE = SOURCE_DIR / "samples" / "steel_ball_h0.2m.wav"
STEREO_SAMPLE = SOURCE_DIR / "samples" / "steel_ball_stereo_44k.wav"


class Cli:
    """The bouncecal command line."""

    def __init__(self, executable):
        self.executable = executable

    def run(self, *arguments, env=None, check=True):
        """Runs `bouncecal ARGUMENTS`; returns the CompletedProcess (text)."""
        completed = subprocess.run(
            [self.executable, *map(str, arguments)], capture_output=True, text=True,
            env={**os.environ, **(env or {})}, timeout=600)
        if check and completed.returncode != 0:
            raise AssertionError(f"bouncecal {' '.join(map(str, arguments))} exited "
                                 f"{completed.returncode}: {completed.stderr}")
        return completed

    def json(self, *arguments, output, env=None):
        """Runs a command that writes --json OUTPUT and returns the parsed file."""
        self.run(*arguments, "--json", output, env=env)
        return json.loads(pathlib.Path(output).read_text())

    def error(self, *arguments):
        """The one-line message and exit status of a command that must fail."""
        completed = self.run(*arguments, check=False)
        assert completed.returncode != 0, f"bouncecal {arguments} succeeded"
        lines = completed.stderr.splitlines()
        assert len(lines) == 1, completed.stderr
        prefix = "bouncecal: error: "
        assert lines[0].startswith(prefix), lines[0]
        return lines[0][len(prefix):], completed.returncode


@pytest.fixture(scope="session")
def cli():
    executable = os.environ.get("BOUNCECAL_EXECUTABLE")
    if not executable or not os.access(executable, os.X_OK):
        pytest.skip("BOUNCECAL_EXECUTABLE (the bouncecal command) is not set; run through ctest")
    return Cli(executable)


@pytest.fixture(scope="session")
def steel_sample():
    return str(STEEL_SAMPLE)
