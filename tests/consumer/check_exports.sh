#!/usr/bin/env bash
# The shared library exports the C ABI and nothing else: every defined dynamic symbol is sf_*
# (plus the version node of capi/statfilter.map).
set -euo pipefail
lib="$1"
symbols=$(nm -D --defined-only "$lib" | awk '{print $3}')
stray=$(echo "$symbols" | grep -v -e '^sf_' -e '^STATFILTER_0$' || true)
count=$(echo "$symbols" | grep -c '^sf_' || true)
if [ -n "$stray" ]; then
  echo "exported symbols outside the C ABI:"; echo "$stray"; exit 1
fi
[ "$count" -ge 40 ] || { echo "only $count sf_ symbols exported"; exit 1; }
echo "exports: $count sf_ symbols, nothing else"
