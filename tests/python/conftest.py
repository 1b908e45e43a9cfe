"""Shared fixtures of the Python module's tests (docs/python.md, docs/testing.md).

ctest runs each file with PYTHONPATH=<build>/python and CLOTHSIM_EXE set to the built `clothsim`
command (tests/python/CMakeLists.txt); by hand:

    PYTHONPATH=build/release/python CLOTHSIM_EXE=build/release/apps/clothsim/clothsim \
        /usr/bin/python3 -m pytest tests/python
"""

import os
import subprocess

import numpy
import pytest

import clothsim


@pytest.fixture
def run_command(tmp_path):
    """Runs the clothsim command with `args` in tmp_path; returns the finished process."""
    exe = os.environ.get("CLOTHSIM_EXE")
    if not exe:
        pytest.skip("CLOTHSIM_EXE (the built clothsim command) is not set")

    def run(*args):
        process = subprocess.run([exe, *args], cwd=tmp_path, capture_output=True, text=True, timeout=600)
        assert process.returncode == 0, process.stderr
        return process

    return run


def short_scene(name="paper-fig5", duration=1.0, **values):
    """A built-in scene cut to `duration` seconds, with further set= values."""
    return clothsim.load_scene(name, set={"output.duration": duration, **values})


def energy_rows(folder):
    """energy.csv as {column: float64 array}."""
    table = numpy.genfromtxt(os.path.join(folder, "energy.csv"), delimiter=",", names=True, dtype=numpy.float64)
    return {name: table[name] for name in table.dtype.names}
