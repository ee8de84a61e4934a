/*
 * The host's rotations (model/include/internal/BodyDynamics.h), which every step of a rotating body
 * on Reference and CPU runs a dozen times: the small-angle sine and cosine must be std::sin and
 * std::cos to rounding, and a rotation of vectors alone (a null Q, as ExactFlow turns the end
 * velocities) must turn them exactly as a rotation of the body does.
 */
#include "ReferenceTests.h"  // the test runner's platform (the functions need none)
#include "internal/BodyDynamics.h"
#include <gtest/gtest.h>
#include <cmath>
#include <random>

using namespace OpenMM;
using namespace RigidLangevinPlugin;

namespace {

/** |a-b| in units of the spacing of doubles at b. */
double ulps(double a, double b) {
    return std::abs(a-b)/(std::nextafter(std::abs(b), 1e300)-std::abs(b));
}

} // namespace

TEST(Rotations, SmallAngleSineAndCosineAreTheLibrarysToRounding) {
    // Every angle the series takes (|x| < 0.1, where a step's rotations are) and across the switch
    // to the library functions. A wrong coefficient (1/5040 as 1/5000) is ~1e5 ulps off at 0.1, a
    // series one term short ~1e-2 ulps; rounding of the sum leaves at most 2.
    std::mt19937_64 engine(3);
    std::uniform_real_distribution<double> uniform(-0.12, 0.12);
    double worstSine = 0, worstCosine = 0;
    for (int i = 0; i < 200000; i++) {
        double x = (i < 1000 ? 1e-3*(i-500)*0.2 : i < 2000 ? 0.1*std::pow(10.0, -0.01*(i-1000)) : uniform(engine));
        double sn, cs;
        BodyDynamics::sineAndCosine(x, sn, cs);
        if (x != 0)
            worstSine = std::max(worstSine, ulps(sn, std::sin(x)));
        worstCosine = std::max(worstCosine, ulps(cs, std::cos(x)));
    }
    EXPECT_LE(worstSine, 2.0);
    EXPECT_LE(worstCosine, 2.0);
    double sn, cs;
    BodyDynamics::sineAndCosine(0.0, sn, cs);
    EXPECT_EQ(0.0, sn);
    EXPECT_EQ(1.0, cs);
}

TEST(Rotations, VectorsAloneTurnAsWithTheBody) {
    BodyType type;
    type.numRotations = 3;
    type.inertia = Vec3(0.7, 1.3, 2.2);
    for (Vec3 phi : {Vec3(0.01, -0.02, 0.005), Vec3(0.4, 0.3, -0.2)}) {
        double q[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        Vec3 withBody[2] = {Vec3(1, 2, 3), Vec3(-0.5, 0.1, 0.9)}, alone[2] = {withBody[0], withBody[1]};
        BodyDynamics::rotateByVector(q, phi, withBody, 2);
        BodyDynamics::rotateByVector(nullptr, phi, alone, 2);
        Vec3 drive(0.3, -0.2, 0.5), driveAlone = drive;
        BodyDynamics::freeRotate(q, type, 0.1, drive, withBody, 2);
        BodyDynamics::freeRotate(nullptr, type, 0.1, driveAlone, alone, 2);
        for (int i = 0; i < 2; i++)
            for (int k = 0; k < 3; k++)
                EXPECT_EQ(withBody[i][k], alone[i][k]);
        for (int k = 0; k < 3; k++)
            EXPECT_EQ(drive[k], driveAlone[k]);
        // The body did turn (the null Q skipped only its rotation).
        EXPECT_GT(std::abs(q[0][1])+std::abs(q[1][2]), 1e-4);
    }
}
