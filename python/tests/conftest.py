# SPDX-License-Identifier: MIT
# Shared fixtures of the Python tests: where the bundled data and the command-line tools are (ctest
# sets FABSYNTH_DATA and FABSYNTH_TOOLS; run by hand, they default to the source tree and build/release).
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("FABSYNTH_DATA", ROOT / "data"))
TOOLS = pathlib.Path(os.environ.get("FABSYNTH_TOOLS", ROOT / "build" / "release" / "examples"))


@pytest.fixture
def data():
    return DATA


@pytest.fixture
def tool():
    """tool("foam_slicer", *args): runs a command-line tool, returns its stdout; skips if it is not built."""
    def run(name, *args):
        exe = TOOLS / name / name
        if not exe.exists():
            pytest.skip(f"{exe} is not built")
        return subprocess.run([str(exe), "--quiet", *map(str, args)], check=True, capture_output=True, text=True).stdout
    return run
