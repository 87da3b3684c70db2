#pragma once
// HAIRLOD_VECTOR_CLONES marks a hot per-vertex loop to be compiled twice, for AVX2 and for the
// baseline, the right one picked when the library loads (target_clones through an ifunc); results
// are the same (no FMA contraction in ISO C++ mode). The function stays out of line so that its
// restrict-qualified arguments keep their no-aliasing facts: GCC needs noinline for that, Clang
// never inlines multiversioned functions and rejects the attribute. Elsewhere: out of line only.
#if defined(__x86_64__) && defined(__clang__)
#define HAIRLOD_VECTOR_CLONES [[gnu::target_clones("avx2", "default")]]
#elif defined(__x86_64__) && defined(__GNUC__)
#define HAIRLOD_VECTOR_CLONES [[gnu::noinline, gnu::target_clones("avx2", "default")]]
#else
#define HAIRLOD_VECTOR_CLONES [[gnu::noinline]]
#endif
