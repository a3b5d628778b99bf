import os
import shutil
import subprocess
from pathlib import Path

import pytest

CLI = os.environ.get("STATFILTER_CLI", "statfilter")
SAMPLE = Path(os.environ.get("STATFILTER_SAMPLE", Path(__file__).resolve().parents[2] / "sample"))
SHARED = Path(os.environ.get("STATFILTER_SHARED_DATA", "/nonexistent"))


def run(*args, check_rc=0, env=None):
    """Runs the CLI; asserts the exit code and returns the completed process."""
    proc = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=300, env=env)
    if check_rc is not None:
        assert proc.returncode == check_rc, f"exit {proc.returncode}\nstdout:{proc.stdout}\nstderr:{proc.stderr}"
    return proc


@pytest.fixture
def sample_noisy():
    return SAMPLE / "cornell_moving" / "spp0004" / "indirect.####.exr"


@pytest.fixture
def small_sequence(tmp_path):
    """The first 4 frames of the shipped sample, copied into a temporary directory."""
    d = tmp_path / "in"
    d.mkdir()
    for f in range(1, 5):
        shutil.copy(SAMPLE / "cornell_moving" / "spp0004" / f"indirect.{f:04d}.exr", d / f"noisy.{f:04d}.exr")
    return d


def oiio_tool(name):
    path = shutil.which(name)
    if not path:
        pytest.skip(f"{name} (openimageio-tools) is not installed")
    return path
