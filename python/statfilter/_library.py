"""Finding and loading the statfilter shared library (libstatfilter.so).

Search order, first hit wins:

1. next to this package: ``statfilter/libstatfilter.so.0``, then ``statfilter/libstatfilter.so``
   (a package staged by the CMake target ``statfilter_python`` or installed from it with pip);
2. the file named by the environment variable ``STATFILTER_LIBRARY``;
3. the system search path, ``ctypes.util.find_library("statfilter")``.

An ImportError lists every place that was tried and why it failed.
"""

import ctypes
import ctypes.util
import os

ENV_VAR = "STATFILTER_LIBRARY"
_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
_BUNDLED_NAMES = ("libstatfilter.so.0", "libstatfilter.so")


def _candidates():
    """(description, path or None) in search order."""
    for name in _BUNDLED_NAMES:
        yield "next to the package", os.path.join(_PACKAGE_DIR, name)
    env = os.environ.get(ENV_VAR)
    yield "$" + ENV_VAR, env if env else None
    yield 'ctypes.util.find_library("statfilter")', ctypes.util.find_library("statfilter")


def load_library():
    """Load the library; returns (ctypes.CDLL, path). Raises ImportError when nothing loads."""
    tried = []
    for where, path in _candidates():
        if not path:
            tried.append("%s: not set / not found" % where)
            continue
        # A bare name from find_library is resolved by the dynamic loader; a path must exist.
        if os.sep in path and not os.path.exists(path):
            tried.append("%s: %s does not exist" % (where, path))
            continue
        try:
            return ctypes.CDLL(path), path
        except OSError as exc:
            tried.append("%s: %s could not be loaded (%s)" % (where, path, exc))
    raise ImportError(
        "statfilter: cannot find the shared library libstatfilter.so. Looked in:\n  - "
        + "\n  - ".join(tried)
        + "\nBuild it (cmake --build build) and either `pip install build/python`, or set "
        + ENV_VAR + " to the path of libstatfilter.so.0."
    )
