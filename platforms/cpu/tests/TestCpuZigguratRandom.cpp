/*
 * The CPU kernel's normal random numbers (ZigguratGaussianRandom): moments and tail probabilities
 * of 2e7 draws against the standard normal's, each within five standard errors; successive draws
 * uncorrelated; the state checkpoints exactly.
 */
#include "CpuTests.h"
#include "ZigguratGaussianRandom.h"
#include <gtest/gtest.h>
#include <cmath>
#include <sstream>

using namespace RigidLangevinPlugin;

TEST(ZigguratRandom, MomentsAndTailsAreNormal) {
    const long n = 20000000;
    ZigguratGaussianRandom random(2024);
    double m1 = 0, m2 = 0, m3 = 0, m4 = 0, m6 = 0, lag1 = 0, previous = 0;
    const double thresholds[] = {0.5, 1.0, 2.0, 3.0, 3.442619855899, 4.0};  // 3.44: where the ziggurat's tail starts
    long above[6] = {0}, below[6] = {0};
    for (long i = 0; i < n; i++) {
        double x = random.next(), x2 = x*x;
        m1 += x;
        m2 += x2;
        m3 += x2*x;
        m4 += x2*x2;
        m6 += x2*x2*x2;
        lag1 += x*previous;
        previous = x;
        for (int t = 0; t < 6; t++) {
            above[t] += (x > thresholds[t]);
            below[t] += (x < -thresholds[t]);
        }
    }
    // Exact moments 0, 1, 0, 3, 15; standard errors sqrt(var(x^k)/n): var of x, x^2, x^3, x^4, x^6
    // is 1, 2, 15, 96, 10170 (moments of the normal: E x^2k = (2k-1)!!).
    double sn = std::sqrt((double) n);
    EXPECT_NEAR(0.0, m1/n, 5/sn);
    EXPECT_NEAR(1.0, m2/n, 5*std::sqrt(2.0)/sn);
    EXPECT_NEAR(0.0, m3/n, 5*std::sqrt(15.0)/sn);
    EXPECT_NEAR(3.0, m4/n, 5*std::sqrt(96.0)/sn);
    EXPECT_NEAR(15.0, m6/n, 5*std::sqrt(10170.0)/sn);
    EXPECT_NEAR(0.0, lag1/n, 5/sn);
    for (int t = 0; t < 6; t++) {
        double p = 0.5*std::erfc(thresholds[t]/std::sqrt(2.0));
        double error = 5*std::sqrt(p*(1-p)/n);
        EXPECT_NEAR(p, (double) above[t]/n, error) << "P(x > " << thresholds[t] << ")";
        EXPECT_NEAR(p, (double) below[t]/n, error) << "P(x < -" << thresholds[t] << ")";
    }
}

TEST(ZigguratRandom, CheckpointContinuesExactly) {
    ZigguratGaussianRandom random(7);
    for (int i = 0; i < 1234; i++)
        random.next();
    std::stringstream checkpoint;
    random.createCheckpoint(checkpoint);
    std::vector<double> first;
    for (int i = 0; i < 3000; i++)
        first.push_back(random.next());
    ZigguratGaussianRandom restored(99);
    restored.loadCheckpoint(checkpoint);
    for (int i = 0; i < 3000; i++)
        ASSERT_EQ(first[i], restored.next()) << "draw " << i;
}
