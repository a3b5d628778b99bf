"""Shared fixtures. Where the package under test comes from:

- ctest: PYTHONPATH points at the package staged in the build tree (<build>/python) and
  STATFILTER_LIBRARY at the library just built;
- STATFILTER_TEST_INSTALLED=1 (scripts/test_wheel.sh): the package installed by pip, which must find
  its own library beside it; importing it from this source tree or a build tree is an error, and
  STATFILTER_LIBRARY must not be set;
- by hand from a source tree: ../../python (then STATFILTER_LIBRARY must name libstatfilter.so.0).
"""

import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
HEADER = os.path.normpath(os.path.join(HERE, "..", "..", "capi", "include", "statfilter", "statfilter.h"))
INSTALLED = os.environ.get("STATFILTER_TEST_INSTALLED") == "1"

if INSTALLED:
    if os.environ.get("STATFILTER_LIBRARY"):
        raise RuntimeError("STATFILTER_TEST_INSTALLED=1 tests the library inside the installed package: "
                           "unset STATFILTER_LIBRARY")
    import statfilter  # noqa: E402

    _package = os.path.dirname(os.path.abspath(statfilter.__file__))
    if "site-packages" not in _package.split(os.sep):
        raise RuntimeError("STATFILTER_TEST_INSTALLED=1 but statfilter was imported from %s, not from an "
                           "installed package" % _package)
    if os.path.dirname(os.path.abspath(statfilter.library_path)) != _package:
        raise RuntimeError("the installed package loaded %s, not its own library" % statfilter.library_path)
else:
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
