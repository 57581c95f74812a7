# SPDX-License-Identifier: MIT
# Shared fixtures of the Python tests: where the bundled data and the command-line tools are (ctest
# sets FABSYNTH_DATA and FABSYNTH_TOOLS; run by hand, they default to the source tree and build/release).
import os
import pathlib
import signal
import subprocess
import sys
import textwrap
import time

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("FABSYNTH_DATA", ROOT / "data"))
TOOLS = pathlib.Path(os.environ.get("FABSYNTH_TOOLS", ROOT / "build" / "release" / "examples"))


@pytest.fixture
def data():
    return DATA


@pytest.fixture
def tool():
    """tool("foam_slicer", *args): runs a command-line tool, returns its stdout; skips if it is not built.
    Comparisons with the library calls pass --no-simplify: the calls return meshes as extracted, the
    tools simplify them by default."""
    def run(name, *args):
        exe = TOOLS / name / name
        if not exe.exists():
            pytest.skip(f"{exe} is not built")
        return subprocess.run([str(exe), "--quiet", *map(str, args)], check=True, capture_output=True, text=True).stdout
    return run


def _interrupt(body, wait_s):
    """Runs `body` (Python source, indented freely) in a child process inside try/except KeyboardInterrupt,
    sends SIGINT `wait_s` seconds after the child prints "started", and returns (exit code, seconds from
    the signal to the child's exit); the child exits 3 when the interrupt reached it as KeyboardInterrupt."""
    script = "import sys\ntry:\n" + textwrap.indent(textwrap.dedent(body), "    ") + \
             "except KeyboardInterrupt:\n    print('interrupted', flush=True)\n    sys.exit(3)\n"
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True, env=dict(os.environ))
    assert child.stdout.readline().strip() == "started"
    time.sleep(wait_s)
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    rc = child.wait(timeout=60)
    elapsed = time.monotonic() - sent
    assert child.stdout.read().strip() == ("interrupted" if rc == 3 else "")
    return rc, elapsed


@pytest.fixture
def interrupt():
    """interrupt(body, wait_s) -> (exit code, seconds to stop): Ctrl-C sent to a child running body."""
    return _interrupt
