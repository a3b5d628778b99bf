#!/usr/bin/env bash
# Installs everything statfilter needs to build and test, from Debian 12 packages and PyPI.
# Idempotent and quick when everything is already present; both README commands call it.
set -euo pipefail

APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libopenimageio-dev openimageio-tools libopenexr-dev libopencolorio-dev
  liblapacke-dev libopenblas-dev libgtest-dev abigail-tools
)
PY_PACKAGES=(numpy pytest)  # and pyoidn, below

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
if ! "$PYTHON" -c "import numpy, pytest" 2>/dev/null; then
  echo "setup: installing ${PY_PACKAGES[*]} for $PYTHON" >&2
  "$PYTHON" -m pip install -q "${PY_PACKAGES[@]}"
fi

# pyoidn ships libOpenImageDenoise, which the oidn plugin loads at run time (its tests skip without
# it). Looked up without importing it; a failed install is a warning, not a failure: statfilter
# builds and passes its other tests without OIDN.
if ! "$PYTHON" -c "import importlib.util, sys; sys.exit(importlib.util.find_spec('pyoidn') is None)" 2>/dev/null; then
  echo "setup: installing pyoidn (Intel Open Image Denoise) for $PYTHON" >&2
  "$PYTHON" -m pip install -q pyoidn || echo "setup: WARNING: pip install pyoidn failed; the oidn plugin's tests will skip" >&2
fi
