// Function multiversioning for the per-pixel float loops. On x86-64 Linux with GCC, a function
// marked SKYPOL_VECTOR_CLONES is compiled twice, for the baseline (SSE2, what every x86-64 runs)
// and for AVX2, and the loader picks one per machine (an ifunc): binaries stay portable, and AVX2
// machines run the loops eight floats wide (what that gains: `skypol bench`, and
// docs/calibration-history.md, "Measurements behind the code's constants"). The AVX2 clone does
// not use FMA, so both clones round every operation alike and output bytes do not depend on the
// machine (checked by comparing whole stacks rendered with and without the clones). Elsewhere the
// macro is empty.
#pragma once

#if defined(__x86_64__) && defined(__linux__) && defined(__GNUC__) && !defined(__clang__)
#define SKYPOL_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SKYPOL_VECTOR_CLONES
#endif
