"""Shared fixtures. ctest runs these tests with PYTHONPATH pointing at the staged package
(<build>/python) and STATFILTER_LIBRARY at the built library. Run by hand from a source tree, the
package is taken from ../../python (then STATFILTER_LIBRARY must name libstatfilter.so.0)."""

import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
HEADER = os.path.normpath(os.path.join(HERE, "..", "..", "capi", "include", "statfilter", "statfilter.h"))

try:
    import statfilter  # noqa: F401
except ImportError:
    sys.path.insert(0, os.path.normpath(os.path.join(HERE, "..", "..", "python")))
    import statfilter  # noqa: F401


@pytest.fixture
def rng():
    return np.random.default_rng(1234)


@pytest.fixture
def noisy(rng):
    """A small (frames, height, width, channels) float32 sequence."""
    return (rng.standard_normal((5, 7, 9, 3)) * 4 + 2).astype(np.float32)


@pytest.fixture
def shared_data():
    """The directory of real renders, or skip when it is not there."""
    path = os.environ.get("STATFILTER_SHARED_DATA", "")
    if not path or not os.path.isdir(path):
        pytest.skip("STATFILTER_SHARED_DATA (%r) is not a directory" % path)
    return path
