"""Points the oidn plugin at the libOpenImageDenoise that the PyPI package ``pyoidn`` ships.

The plugin (C) reads ``$STATFILTER_OIDN_LIBRARY``. When that is unset and ``pyoidn`` is installed
in this Python, it is set to the library inside that package before the plugin is first loaded.
``pyoidn`` is located without being imported.
"""

import importlib.util
import os

ENV_VAR = "STATFILTER_OIDN_LIBRARY"


def pyoidn_library():
    """Path of pyoidn's bundled libOpenImageDenoise.so.2, or None."""
    try:
        spec = importlib.util.find_spec("pyoidn")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.origin:
        return None
    path = os.path.join(os.path.dirname(spec.origin), "oidn", "lib", "libOpenImageDenoise.so.2")
    return path if os.path.exists(path) else None


def use_pyoidn_if_unset():
    if os.environ.get(ENV_VAR):
        return
    path = pyoidn_library()
    if path:
        os.environ[ENV_VAR] = path
