#pragma once

#include <cstdint>

// SF_VECTOR_CLONES on a loop-heavy function: an AVX2 build of it and a baseline (SSE2) one, chosen
// when the library loads. No FMA in either, so both give the same bits. Not under ThreadSanitizer:
// the clones' resolver runs before its runtime is up and crashes the process.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_THREAD__)
#define SF_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SF_VECTOR_CLONES
#endif

namespace statfilter {
// Four doubles side by side, one AVX2 register or two SSE2 ones (GCC's and Clang's vector extension):
// a comparison is one vector compare giving a lane mask, and `mask ? a : b` one select, whatever the
// instruction set a clone is built for.
typedef double Lanes __attribute__((vector_size(4 * sizeof(double))));
typedef int64_t LaneMask __attribute__((vector_size(4 * sizeof(int64_t))));
}  // namespace statfilter
