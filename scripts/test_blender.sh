#!/usr/bin/env bash
# The Blender hand-off rendering real windows: bpy (Blender as a Python module, from PyPI) in a venv of
# its own (it pins numpy < 2, and it is ~400 MB, so it stays out of the project's own environment),
# then tests/handoff with STATFILTER_BPY_PYTHON naming it. Fails when the render tests skip, so CI
# cannot pass without rendering. Usage: scripts/test_blender.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${1:-build}"
venv="$build_dir/bpy-venv"
if ! "$venv/bin/python" -c "import bpy" 2>/dev/null; then
  echo "test_blender: installing bpy into $venv" >&2
  python3 -m venv "$venv"
  "$venv/bin/python" -m pip install -q bpy
fi
out=$(STATFILTER_BPY_PYTHON="$PWD/$venv/bin/python" PYTHONPATH="$build_dir/python" \
      STATFILTER_LIBRARY="$build_dir/capi/libstatfilter.so" STATFILTER_CLI="$build_dir/tools/statfilter" \
      PYTHONDONTWRITEBYTECODE=1 python3 -m pytest -q -rs -p no:cacheprovider tests/handoff 2>&1) || { echo "$out"; exit 1; }
echo "$out" | tail -3
if echo "$out" | grep -q "skipped"; then
  echo "test_blender: the Blender render tests skipped" >&2
  exit 1
fi
