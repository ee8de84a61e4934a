#ifndef RIGID_LANGEVIN_TARGET_CLONES_H_
#define RIGID_LANGEVIN_TARGET_CLONES_H_

/**
 * RIGIDLANGEVIN_CLONES compiles a hot loop in two builds, one for CPUs with AVX2 and FMA
 * (x86-64-v3) and one for the baseline, of which the CPU picks one when the library is loaded (GCC's
 * target_clones, an ELF ifunc); flatten compiles everything it calls inline into each build. Other
 * compilers build the baseline.
 */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__ELF__)
#define RIGIDLANGEVIN_CLONES __attribute__((target_clones("arch=x86-64-v3", "default"), flatten))
#else
#define RIGIDLANGEVIN_CLONES
#endif

#endif /*RIGID_LANGEVIN_TARGET_CLONES_H_*/
