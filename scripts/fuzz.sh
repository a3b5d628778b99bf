#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang in their own build directory and runs each for
# SECONDS seconds on a freshly generated seed corpus. Exits non-zero on the first finding; the input
# that triggered it is kept under BUILD_DIR/findings/. Usage: scripts/fuzz.sh SECONDS [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:?usage: scripts/fuzz.sh SECONDS [BUILD_DIR]}"
build_dir="${2:-build-fuzz}"
CC=clang CXX=clang++ bash scripts/build.sh "$build_dir" -DSTATFILTER_FUZZ=ON

seeds="$build_dir/seeds"
rm -rf "$seeds"
bash fuzz/make_seeds.sh "$seeds"
mkdir -p "$build_dir/findings"
# Leaks of the (uninstrumented) image libraries' caches are not findings; memory beyond 4 GB is.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
for target in sequence_reader:exr crops:crops cli_args:cli; do
  name="${target%%:*}"; corpus_seeds="$seeds/${target##*:}"
  corpus="$build_dir/corpus/$name"  # what the fuzzer learns, kept between runs
  mkdir -p "$corpus"
  echo "== fuzz_$name for ${seconds}s"
  status=0
  "$build_dir/fuzz/fuzz_$name" "$corpus" "$corpus_seeds" -max_total_time="$seconds" -timeout=20 \
    -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$build_dir/findings/$name-" \
    > "$build_dir/fuzz_$name.log" 2>&1 || status=$?
  if [ "$status" -ne 0 ]; then
    tail -n 60 "$build_dir/fuzz_$name.log"
    echo "fuzz_$name: finding (exit $status), input in $build_dir/findings/"; exit 1
  fi
  grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$build_dir/fuzz_$name.log" || true
done
echo "fuzz: no finding in ${seconds}s per target"
