#!/usr/bin/env bash
# Installs everything statfilter needs to build and test, from Debian 12 packages and PyPI.
# Idempotent and quick when everything is already present; both README commands call it.
set -euo pipefail

APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libopenimageio-dev openimageio-tools libopenexr-dev libopencolorio-dev
  liblapacke-dev libopenblas-dev libgtest-dev abigail-tools
  python3-venv  # scripts/test_wheel.sh: the wheel tested in a fresh venv
  time  # /usr/bin/time: peak memory in bench/
  clang libclang-rt-dev  # libFuzzer, for scripts/fuzz.sh
  chromium  # headless screenshot of the review page (tests/python/test_report.py)
)
PY_PACKAGES=(numpy pytest jsonschema "dask[distributed]")  # and pyoidn, below; jsonschema: tests/cli/test_crops_schema.py;
# dask[distributed]: tests/python/test_distributed.py (the package itself works without it)

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

PYTHON="${PYTHON:-python3}"
# A Debian system Python refuses plain pip installs (PEP 668); retry the way Debian allows.
pip_install() {
  "$PYTHON" -m pip install -q "$@" 2>/dev/null || "$PYTHON" -m pip install -q --break-system-packages "$@"
}
if ! "$PYTHON" -c "import numpy, pytest, jsonschema, dask.distributed" 2>/dev/null; then
  echo "setup: installing ${PY_PACKAGES[*]} for $PYTHON" >&2
  pip_install "${PY_PACKAGES[@]}"
fi

# pyoidn ships libOpenImageDenoise, which the oidn plugin loads at run time (its tests skip without
# it). Looked up without importing it. For a user a failed install is a warning (statfilter builds
# and passes its other tests without OIDN); in CI it is an error, so the plugin's tests cannot rot.
if ! "$PYTHON" -c "import importlib.util, sys; sys.exit(importlib.util.find_spec('pyoidn') is None)" 2>/dev/null; then
  echo "setup: installing pyoidn (Intel Open Image Denoise) for $PYTHON" >&2
  if ! pip_install pyoidn; then
    [ "${CI:-}" = "true" ] && { echo "setup: pip install pyoidn failed" >&2; exit 1; }
    echo "setup: WARNING: pip install pyoidn failed; the oidn plugin's tests will skip" >&2
  fi
fi
