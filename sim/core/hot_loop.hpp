// DEM2D_HOT: a function whose loops a portable build (DEM2D_MULTIVERSION)
// compiles three times, for any x86-64, for x86-64-v3 (AVX2) and for
// x86-64-v4 (AVX-512), running the one the CPU can (GCC's function
// multi-versioning, chosen when the program starts): one build runs on any
// node at nearly a native build's speed. Every version gives the same results
// bit for bit: no fused multiply-add (-ffp-contract=off) and no reordered sums
// (measured: the quick fill's run file from this build, from one with the -v3
// version only and from one without versions are equal, bit for bit, on an
// AVX-512 CPU; docs/install.md). Used by the engine's contact loops and the
// coarse-graining's sums.
#pragma once

#ifdef DEM2D_MULTIVERSION
#define DEM2D_HOT __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#else
#define DEM2D_HOT
#endif
