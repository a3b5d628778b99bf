#!/usr/bin/env bash
# The fuzz targets (built without libFuzzer, with replay_main.cpp) over a freshly generated seed
# corpus: each input must run without a crash or sanitizer report.
# Usage: fuzz/run_seeds.sh FUZZ_SOURCE_DIR READER CROPS CLI_ARGS
set -euo pipefail
source_dir="$1"; reader="$2"; crops="$3"; cli_args="$4"
seeds=$(mktemp -d)
trap 'rm -rf "$seeds"' EXIT
bash "$source_dir/make_seeds.sh" "$seeds"
"$reader" "$seeds/exr"
"$crops" "$seeds/crops"
"$cli_args" "$seeds/cli"
