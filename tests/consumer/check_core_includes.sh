#!/usr/bin/env bash
# The C++ core (lib/) never includes the library's public C headers: only lib/plugins/ includes one,
# the plugin interface (statfilter_plugin.h), to read plugins' structs into core types
# (docs/architecture.md). Usage: check_core_includes.sh SOURCE_DIR
set -euo pipefail
cd "$1/lib"
public=$(grep -rnE '#include *[<"](statfilter/)?statfilter(_types)?\.h[">]' . || true)
plugin=$(grep -rnE '#include *[<"](statfilter/)?statfilter_plugin\.h[">]' . | grep -v '^\./plugins/' || true)
if [ -n "$public$plugin" ]; then
  echo "check_core_includes: lib/ includes a public C header outside lib/plugins/:" >&2
  printf '%s\n' "$public" "$plugin" | grep . >&2
  exit 1
fi
echo "check_core_includes: lib/ includes no public C header outside lib/plugins/ (statfilter_plugin.h only)"
