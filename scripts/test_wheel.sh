#!/usr/bin/env bash
# Builds the Python wheel from the repository root (pip wheel ., scikit-build-core driving CMake in
# Release, the library and its plugins only), installs it into a fresh venv, and runs the Python
# tests (tests/python) against the installed package, not the build tree.
# Usage: scripts/test_wheel.sh [WORK_DIR]   (default build-wheel; the CMake build is kept there
# for the next run, so a second run rebuilds only what changed)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work="${1:-build-wheel}"
mkdir -p "$work"
work=$(cd "$work" && pwd)
PYTHON="${PYTHON:-python3}"

rm -rf "$work/dist" "$work/venv"
echo "== pip wheel . (into $work/dist)"
"$PYTHON" -m pip wheel --no-deps -q -w "$work/dist" .
wheel=$(ls "$work"/dist/statfilter-*.whl)
echo "wheel: $(basename "$wheel") ($(du -k "$wheel" | cut -f1) kB)"

echo "== fresh venv, pip install the wheel"
"$PYTHON" -m venv "$work/venv"
venv_python="$work/venv/bin/python"
"$venv_python" -m pip install -q "$wheel" pytest

echo "== tests/python against the installed package"
# Outside the source tree, so that nothing is imported from it; no STATFILTER_LIBRARY: the package
# must find its own library (tests/python/conftest.py checks both).
cd "$work"
env -u STATFILTER_LIBRARY -u PYTHONPATH STATFILTER_TEST_INSTALLED=1 PYTHONDONTWRITEBYTECODE=1 \
  STATFILTER_SHARED_DATA="${STATFILTER_SHARED_DATA:-$root/../shared/data}" \
  "$venv_python" -m pytest -q -p no:cacheprovider "$root/tests/python"
