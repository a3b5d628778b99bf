"""Fixtures for the plugin tests: the staged Python package (PYTHONPATH), the CLI, the plugin
directory with the test plugins (STATFILTER_PLUGIN_PATH), and whether the oidn plugin can run."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
try:
    import statfilter  # noqa: F401
except ImportError:
    sys.path.insert(0, str(HERE.parents[1] / "python"))
    import statfilter  # noqa: F401

CLI = os.environ.get("STATFILTER_CLI", "statfilter")
SAMPLE = Path(os.environ.get("STATFILTER_SAMPLE", HERE.parents[1] / "sample"))
SHARED = Path(os.environ.get("STATFILTER_SHARED_DATA", "/nonexistent"))


def run_cli(*args, check_rc=0, env=None):
    proc = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=600,
                          env=None if env is None else {**os.environ, **env})
    if check_rc is not None:
        assert proc.returncode == check_rc, f"exit {proc.returncode}\nstdout:{proc.stdout}\nstderr:{proc.stderr}"
    return proc


def oidn_info():
    for p in statfilter.plugins():
        if p["name"] == "oidn":
            return p
    return None


@pytest.fixture
def oidn():
    """Skips, saying why, unless the oidn plugin is there and libOpenImageDenoise loads."""
    info = oidn_info()
    if info is None:
        pytest.skip("the oidn plugin was not found next to the library")
    if not info["available"]:
        pytest.skip("oidn cannot run on this machine: " + info["problem"].splitlines()[0])
    return info
