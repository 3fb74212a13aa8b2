#pragma once
// BUSHEL_VECTOR_CLONES before a function that loops over structure-of-arrays lanes builds it
// three times where the compiler and the C library allow it: for AVX-512 (8 doubles per
// instruction), AVX2 and the baseline, chosen once at load time by the processor. All give
// the same bits (no contraction into fused multiply-adds: -ffp-contract=off). The file that
// holds such a function is built without math errno and FP traps (src/CMakeLists.txt), so
// that a square root vectorises.

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define BUSHEL_VECTOR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define BUSHEL_VECTOR_CLONES
#endif
