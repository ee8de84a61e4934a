/**
 * Normal random numbers made where a step uses them. Philox4x32-10 (Salmon, Moraes, Dror and Shaw,
 * SC11) is counter-based: its output is a function of a key (the seed) and a counter (the body, the
 * draw and the step), with no state to keep, so each body draws its own numbers in the step kernel
 * instead of reading them from a buffer another kernel wrote: that buffer was 192 of the ~1050 bytes
 * a step moved per three-particle body. tests/TestRandomNumbers.cpp checks these rounds bit for bit
 * against Random123's philox4x32 (the authors' library) and the normal numbers' moments.
 *
 * Written in the common subset of OpenCL C, CUDA and C++, with unsigned int (32 bits everywhere)
 * and mm_ulong for the 32x32 -> 64-bit products, so that the host test can compile it as it is.
 */

#define PHILOX_M0 0xD2511F53u
#define PHILOX_M1 0xCD9E8D57u
#define PHILOX_W0 0x9E3779B9u
#define PHILOX_W1 0xBB67AE85u

/** Philox4x32 with ten rounds: c (the counter) becomes the four random words of key (k0, k1). */
DEVICE void philox4x32R10(unsigned int* c, unsigned int k0, unsigned int k1) {
    for (int round = 0; round < 10; round++) {
        mm_ulong p0 = (mm_ulong) PHILOX_M0*c[0];
        mm_ulong p1 = (mm_ulong) PHILOX_M1*c[2];
        unsigned int hi0 = (unsigned int) (p0 >> 32), lo0 = (unsigned int) p0;
        unsigned int hi1 = (unsigned int) (p1 >> 32), lo1 = (unsigned int) p1;
        c[0] = hi1^c[1]^k0;
        c[1] = lo1;
        c[2] = hi0^c[3]^k1;
        c[3] = lo0;
        k0 += PHILOX_W0;
        k1 += PHILOX_W1;
    }
}

/**
 * sin(pi x) and cos(pi x). Box-Muller's angle is a fraction of a turn: taken in half turns, it needs
 * none of the reduction of an argument in radians that sin and cos do (on PoCL that reduction took
 * 12% of an OpenCL test's time). The host test's C++ has no sinpi.
 */
DEVICE void sinCosPi(float x, float* s, float* c) {
#if defined(__OPENCL_VERSION__)
    *s = sinpi(x);
    *c = cospi(x);
#elif defined(__CUDACC__)
    sincospif(x, s, c);
#else
    *s = sin(3.14159265358979f*x);
    *c = cos(3.14159265358979f*x);
#endif
}

/** Two independent standard normal numbers from two random words (Box-Muller). */
DEVICE void boxMuller(unsigned int a, unsigned int b, float* n) {
    // u in (0, 1] so that the logarithm is finite: 24-bit uniforms, as many bits as a float holds.
    float u = ((a >> 8)+1)*(1.0f/16777216.0f);
    float halfTurns = (b >> 8)*(2.0f/16777216.0f);  // the angle in [0, 2 pi), over pi
    float r = sqrt(-2.0f*log(u));
    float s, c;
    sinCosPi(halfTurns, &s, &c);
    n[0] = r*c;
    n[1] = r*s;
}

/**
 * The i-th four normal numbers of body `body` at step `step` for the generator seeded with `seed`:
 * every (body, i, step) is a counter of its own, so no two draws of a run share their numbers.
 */
DEVICE void normalFloat4(unsigned int seed, int body, int i, mm_ulong step, float* n) {
    unsigned int c[4] = {(unsigned int) body, (unsigned int) i, (unsigned int) step, (unsigned int) (step >> 32)};
    philox4x32R10(c, seed, 0x52676964u);
    boxMuller(c[0], c[1], n);
    boxMuller(c[2], c[3], n+2);
}
