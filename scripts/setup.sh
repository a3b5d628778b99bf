#!/usr/bin/env bash
# Installs everything statfilter needs to build and test, from Debian 12 packages and PyPI.
# Idempotent and quick when everything is already present; both README commands call it.
set -euo pipefail

APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libopenimageio-dev openimageio-tools libopenexr-dev libopencolorio-dev
  liblapacke-dev libopenblas-dev libgtest-dev abigail-tools
)
PY_PACKAGES=(numpy pytest)

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
