#!/usr/bin/env bash
# Runs every test: installs what is missing, builds, then C++, Python, CLI and consumer tests via ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh build
cd build
ctest --output-on-failure -j "$(nproc)"
