"""Points the oidn plugin at the libOpenImageDenoise that the PyPI package ``pyoidn`` ships.

The plugin (C) reads ``$STATFILTER_OIDN_LIBRARY``. When that is unset and ``pyoidn`` is installed
in this Python, it is set to the library inside that package before the plugin is first loaded.
``pyoidn`` is located without being imported, and only among the installed packages (the
site-packages directories): a ``pyoidn`` folder in the working directory or on ``sys.path`` is
never taken, so whoever controls the working directory cannot choose the library that is loaded.
"""

import importlib.machinery
import os
import site
import sysconfig

ENV_VAR = "STATFILTER_OIDN_LIBRARY"


def _site_directories():
    """The directories packages are installed into, for this interpreter (or its venv)."""
    dirs = [sysconfig.get_paths().get(key) for key in ("purelib", "platlib")]
    dirs += getattr(site, "getsitepackages", lambda: [])()
    if site.ENABLE_USER_SITE:
        dirs.append(site.getusersitepackages())
    seen, out = set(), []
    for d in dirs:
        if d and os.path.isabs(d) and d not in seen:
            seen.add(d)
            out.append(d)
    return out


def pyoidn_library():
    """Path of the installed pyoidn's bundled libOpenImageDenoise.so.2, or None."""
    try:
        spec = importlib.machinery.PathFinder.find_spec("pyoidn", _site_directories())
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
