#pragma once

// SF_VECTOR_CLONES on a loop-heavy function: an AVX2 build of it and a baseline (SSE2) one, chosen
// when the library loads. No FMA in either, so both give the same bits. Not under ThreadSanitizer:
// the clones' resolver runs before its runtime is up and crashes the process.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_THREAD__)
#define SF_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SF_VECTOR_CLONES
#endif
