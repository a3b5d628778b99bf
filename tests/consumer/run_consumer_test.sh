#!/usr/bin/env bash
# Installs the built statfilter into a temporary prefix, then builds and runs a C program against it
# twice: through find_package(statfilter) and through pkg-config.
set -euo pipefail
build_dir="$1"; source_dir="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
libdir=$(ls -d "$work"/prefix/lib*/ | head -n1)
# The installed tool, library and plugin search no directory relative to the working directory.
bash "$source_dir/check_runpath.sh" "$work/prefix/bin/statfilter" "$libdir"libstatfilter.so.0 "$libdir"statfilter_oidn.so >/dev/null
"$work/prefix/bin/statfilter" version >/dev/null  # finds its library through $ORIGIN alone
export LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

cmake -S "$source_dir/project" -B "$work/cmake-build" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/cmake-build" >/dev/null
"$work/cmake-build/consumer"

export PKG_CONFIG_PATH="$libdir/pkgconfig"
cc ${CFLAGS:-} -o "$work/consumer-pc" "$source_dir/project/consumer.c" $(pkg-config --cflags --libs statfilter) ${LDFLAGS:-}
"$work/consumer-pc"
