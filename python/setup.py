"""Only here to tag the wheel correctly: everything else is in pyproject.toml.

When the CMake target statfilter_python has staged libstatfilter.so next to the .py files, the
wheel carries a platform binary and must not be tagged pure Python (py3-none-any)."""

import glob
import os

from setuptools import setup
from setuptools.dist import Distribution

HERE = os.path.dirname(os.path.abspath(__file__))
BUNDLES_LIBRARY = bool(glob.glob(os.path.join(HERE, "statfilter", "libstatfilter.so*")))


class StatfilterDistribution(Distribution):
    def has_ext_modules(self):
        return BUNDLES_LIBRARY or super().has_ext_modules()


cmdclass = {}
try:
    try:
        from setuptools.command.bdist_wheel import bdist_wheel
    except ImportError:
        from wheel.bdist_wheel import bdist_wheel

    class bdist_wheel_ctypes(bdist_wheel):
        """ctypes works with any Python 3: tag py3-none-<platform>, not cpXY-cpXY-<platform>."""

        def get_tag(self):
            python, abi, platform = super().get_tag()
            return ("py3", "none", platform) if BUNDLES_LIBRARY else (python, abi, platform)

    cmdclass["bdist_wheel"] = bdist_wheel_ctypes
except ImportError:  # no wheel support installed: pip installs without building a wheel
    pass

setup(distclass=StatfilterDistribution, cmdclass=cmdclass)
