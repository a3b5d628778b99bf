#!/usr/bin/env bash
# ThreadSanitizer over the thread-safety contract (docs/architecture.md): separate filter objects on
# separate threads, motion compensation included, give the sequential results with no data race.
# OpenCV's and OpenBLAS's own pools are not instrumented, so they run serial here (the test's
# OpenCVSerial case); the test itself runs the filters on two std::threads.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${1:-build-tsan}"
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_C_FLAGS=-fsanitize=thread -DCMAKE_CXX_FLAGS=-fsanitize=thread \
    -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread -DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=thread >/dev/null
fi
cmake --build "$build_dir" --target test_motion_threads
OPENBLAS_NUM_THREADS=1 TSAN_OPTIONS="halt_on_error=1" "$build_dir/tests/filters/test_motion_threads" --gtest_filter='*OpenCVSerial*'
