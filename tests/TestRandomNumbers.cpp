/*
 * The common platforms' random numbers (platforms/common/src/kernels/rigidBodyRandom.cc), compiled
 * here on the host as the devices compile it: its Philox4x32-10 must give Random123's philox4x32
 * (the generator's authors' library) bit for bit, and its normal numbers the moments of a standard
 * normal distribution, independent between draws, bodies and steps.
 */
#include "ReferenceTests.h"  // the test runner's platform (the numbers need none)
#include <Random123/philox.h>
#include <gtest/gtest.h>
#include <cmath>
#include <vector>

// The device dialect's names for the host: float overloads of the math functions, as on the devices.
#define DEVICE static inline
typedef unsigned long long mm_ulong;
using std::cos;
using std::log;
using std::sin;
using std::sqrt;
#include "../platforms/common/src/kernels/rigidBodyRandom.cc"

TEST(RandomNumbers, PhiloxMatchesRandom123) {
    // Counters and keys with every word zero, all ones, and scrambled patterns.
    unsigned int word = 0x12345678u;
    for (int trial = 0; trial < 1000; trial++) {
        unsigned int values[6];
        for (unsigned int& v : values) {
            word = word*1664525u+1013904223u;
            v = (trial == 0 ? 0u : trial == 1 ? 0xFFFFFFFFu : word);
        }
        philox4x32_ctr_t counter = {{values[0], values[1], values[2], values[3]}};
        philox4x32_key_t key = {{values[4], values[5]}};
        philox4x32_ctr_t expected = philox4x32(counter, key);
        unsigned int c[4] = {values[0], values[1], values[2], values[3]};
        philox4x32R10(c, values[4], values[5]);
        for (int i = 0; i < 4; i++)
            ASSERT_EQ(expected.v[i], c[i]) << "trial " << trial << ", word " << i;
    }
}

TEST(RandomNumbers, NormalMomentsAndIndependence) {
    // 2^20 numbers: 64 bodies x 4 draws x 1024 steps. Each moment is held to 4 of its standard
    // errors (mean 0.004, variance 0.0055, fourth moment 0.038, correlations 0.004-0.008): a
    // variance off by 2% fails, as would numbers repeated between bodies, draws or steps.
    const int bodies = 64, draws = 4, steps = 1024;
    std::vector<float> n((size_t) bodies*draws*steps*4);
    for (int step = 0; step < steps; step++)
        for (int body = 0; body < bodies; body++)
            for (int i = 0; i < draws; i++)
                normalFloat4(1234u, body, i, (mm_ulong) step+(1ull << 32), &n[(((size_t) step*bodies+body)*draws+i)*4]);
    double sum = 0, sum2 = 0, sum4 = 0;
    for (float x : n) {
        sum += x;
        sum2 += x*x;
        sum4 += (double) x*x*x*x;
    }
    const double count = n.size();
    EXPECT_NEAR(0.0, sum/count, 4/sqrt(count));
    EXPECT_NEAR(1.0, sum2/count, 4*sqrt(2/count));
    EXPECT_NEAR(3.0, sum4/count, 4*sqrt(96/count));
    // The same number of the next step, the next body and the next draw: uncorrelated.
    const size_t stride[3] = {(size_t) bodies*draws*4, (size_t) draws*4, 4};
    for (size_t s : stride) {
        double product = 0;
        for (size_t k = 0; k+s < n.size(); k++)
            product += n[k]*n[k+s];
        EXPECT_NEAR(0.0, product/(n.size()-s), 4/sqrt((double) (n.size()-s))) << "stride " << s;
    }
    // The four numbers of one draw: uncorrelated (two Box-Muller pairs).
    double pair = 0, across = 0;
    for (size_t k = 0; k < n.size(); k += 4) {
        pair += n[k]*n[k+1];
        across += n[k+1]*n[k+2];
    }
    EXPECT_NEAR(0.0, pair/(count/4), 4/sqrt(count/4));
    EXPECT_NEAR(0.0, across/(count/4), 4/sqrt(count/4));
}
