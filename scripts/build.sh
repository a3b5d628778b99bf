#!/usr/bin/env bash
# Configures and builds statfilter (RelWithDebInfo: the ABI check reads its debug info; benchmarks build
# Release with -DCMAKE_BUILD_TYPE=Release). Usage: scripts/build.sh [BUILD_DIR] [extra cmake args...]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${1:-build}"
shift || true
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
fi
cmake --build "$build_dir"
