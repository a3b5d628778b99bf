#!/usr/bin/env bash
# Compares the built C ABI with the baseline in abi/. Any difference fails: an incompatible change
# must not happen within a soname; a compatible one (a new function) is accepted by updating the
# baseline on purpose with --update, in the same commit as the header change.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
lib="$build_dir/capi/libstatfilter.so"
baseline=abi/libstatfilter.abi
abidw_args=(--headers-dir capi/include/statfilter --drop-private-types --no-corpus-path --no-show-locs --no-comp-dir-path)

[ -f "$lib" ] || { echo "abi_check: $lib not built" >&2; exit 1; }
# abidw records each translation unit's source path: make them relative to the checkout so the
# baseline is the same on every machine.
dump() { abidw "${abidw_args[@]}" "$lib" | sed "s#path='$PWD/#path='#g" > "$1"; }

if [ "${1:-}" = "--update" ]; then
  dump "$baseline"
  echo "abi_check: baseline written to $baseline"
  exit 0
fi

current=$(mktemp --suffix=.abi)
trap 'rm -f "$current"' EXIT
dump "$current"
set +e
abidiff --no-added-syms "$baseline" "$current" >/dev/null
quiet_rc=$?
abidiff "$baseline" "$current"
rc=$?
set -e
if [ $rc -eq 0 ]; then
  echo "abi_check: the C ABI matches $baseline"
  exit 0
fi
if [ $((rc & 8)) -ne 0 ]; then
  echo "abi_check: INCOMPATIBLE change to the C ABI (abidiff exit $rc)" >&2
elif [ $quiet_rc -eq 0 ]; then
  echo "abi_check: functions were added; if intended, run scripts/abi_check.sh --update and commit $baseline" >&2
else
  echo "abi_check: the C ABI changed (abidiff exit $rc); see above" >&2
fi
exit 1
