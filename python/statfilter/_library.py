"""Finding and loading the statfilter shared library (libstatfilter.so).

Search order, first hit wins:

1. next to this package: ``statfilter/libstatfilter.so.0``, then ``statfilter/libstatfilter.so``
   (an installed wheel, or the package staged by the CMake target ``statfilter_python``);
2. the file named by the environment variable ``STATFILTER_LIBRARY``;
3. the system search path, ``ctypes.util.find_library("statfilter")``.

The library links shared libraries of the system (OpenImageIO, OpenColorIO, OpenCV, LAPACKE,
OpenBLAS: python/README.md) that a wheel does not carry. When one is missing, the ImportError says
which, and which Debian 12 package provides it; otherwise it lists every place that was tried.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import re
from typing import Iterator, List, Optional, Tuple

ENV_VAR = "STATFILTER_LIBRARY"
_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
_BUNDLED_NAMES = ("libstatfilter.so.0", "libstatfilter.so")

#: The system libraries libstatfilter links (its DT_NEEDED beyond the C and C++ runtimes) and the
#: Debian 12 packages that provide them. Kept in step with python/README.md.
SYSTEM_LIBRARIES = {
    "libOpenImageIO.so.2.4": "libopenimageio2.4",
    "libOpenImageIO_Util.so.2.4": "libopenimageio2.4",
    "libOpenColorIO.so.2.1": "libopencolorio2.1",
    "libOpenEXR-3_1.so.30": "libopenexr-3-1-30",
    "libImath-3_1.so.29": "libimath-3-1-29",
    "libopencv_core.so.406": "libopencv-core406",
    "libopencv_imgproc.so.406": "libopencv-imgproc406",
    "libopencv_video.so.406": "libopencv-video406",
    "liblapacke.so.3": "liblapacke",
    "libopenblas.so.0": "libopenblas0",
}

_MISSING = re.compile(r"([^\s:]+\.so[^\s:]*): cannot open shared object file")


def missing_system_library_message(path: str, error: str) -> Optional[str]:
    """The ImportError text when loading ``path`` failed because a library it needs is missing
    (``error`` is the loader's message), or None for any other failure."""
    found = _MISSING.search(error)
    if not found or os.path.basename(found.group(1)).startswith("libstatfilter"):
        return None
    missing = found.group(1)
    package = SYSTEM_LIBRARIES.get(missing)
    packages = " ".join(sorted(set(SYSTEM_LIBRARIES.values())))
    return (
        "statfilter: the library %s needs %s, which is not installed%s.\n"
        "The statfilter wheel links these system libraries (Debian 12 packages): install them with\n"
        "  apt-get install %s\n"
        "or build statfilter from source on this system (pip install . in the project)."
        % (path, missing, " (Debian 12 package %s)" % package if package else "", packages)
    )


def _candidates() -> Iterator[Tuple[str, Optional[str]]]:
    """(description, path or None) in search order."""
    for name in _BUNDLED_NAMES:
        yield "next to the package", os.path.join(_PACKAGE_DIR, name)
    env = os.environ.get(ENV_VAR)
    yield "$" + ENV_VAR, env if env else None
    yield 'ctypes.util.find_library("statfilter")', ctypes.util.find_library("statfilter")


def load_library() -> Tuple[ctypes.CDLL, str]:
    """Load the library; returns (ctypes.CDLL, path). Raises ImportError when nothing loads."""
    tried: List[str] = []
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
            # The library is there but the system lacks what it links: that, not the search, is the problem.
            message = missing_system_library_message(path, str(exc))
            if message:
                raise ImportError(message) from exc
            tried.append("%s: %s could not be loaded (%s)" % (where, path, exc))
    raise ImportError(
        "statfilter: cannot find the shared library libstatfilter.so. Looked in:\n  - "
        + "\n  - ".join(tried)
        + "\nInstall the package (pip install . in the project), or build it (cmake --build build) and set "
        + ENV_VAR + " to the path of libstatfilter.so.0."
    )
