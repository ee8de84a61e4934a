/*
 * The host's rotations (model/include/internal/BodyDynamics.h), which every step of a rotating body
 * on Reference and CPU runs a dozen times: the small-angle sine and cosine must be std::sin and
 * std::cos to rounding, and a rotation of vectors alone (a null Q, as ExactFlow turns the end
 * velocities) must turn them exactly as a rotation of the body does, and the frame's and the
 * vectors' rotations interleaved must be the separate ones bit for bit. The common platforms' own
 * (platforms/common/src/kernels/rigidBodyMath.cc), compiled here on the host as the devices compile
 * it, in each precision of its "mixed" type: their series must round as the library does too.
 */
#include "ReferenceTests.h"  // the test runner's platform (the functions need none)
#include "internal/BodyDynamics.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <random>

using namespace OpenMM;
using namespace RigidLangevinPlugin;

// The device source in the host's dialect, once with mixed as double (mixed and double precision)
// and once as float (single precision).
#define DEVICE static inline
namespace DeviceDouble {
typedef double mixed;
static inline void sincos(double x, double* s, double* c) {
    *s = std::sin(x);
    *c = std::cos(x);
}
using std::sqrt;
#define USE_DOUBLE_PRECISION
#include "../platforms/common/src/kernels/rigidBodyMath.cc"
#undef USE_DOUBLE_PRECISION
}
namespace DeviceSingle {
typedef float mixed;
static inline void sincos(float x, float* s, float* c) {
    *s = std::sin(x);
    *c = std::cos(x);
}
using std::sqrt;
#include "../platforms/common/src/kernels/rigidBodyMath.cc"
}
#undef DEVICE

namespace {

/** |a-b| in units of the spacing of doubles (or floats) at b. */
template <class Real>
double ulps(Real a, Real b) {
    return std::abs((double) a-(double) b)/((double) std::nextafter(std::abs(b), (Real) 1e30)-(double) std::abs(b));
}

/**
 * The largest error, in ulps of the exact value, of sineAndCosine(x, sn, cs) over the angles a step
 * turns by (|x| < 0.1, where the series are used) and across the switch to the library functions:
 * evenly spaced, log-spaced down to 1e-11, then random. The exact values are std::sin and std::cos
 * in long double, rounded to Real.
 */
template <class Real, class SineAndCosine>
void worstErrors(SineAndCosine sineAndCosine, double& worstSine, double& worstCosine) {
    std::mt19937_64 engine(3);
    std::uniform_real_distribution<double> uniform(-0.12, 0.12);
    worstSine = worstCosine = 0;
    for (int i = 0; i < 200000; i++) {
        Real x = (Real) (i < 1000 ? 1e-3*(i-500)*0.2 : i < 2000 ? 0.1*std::pow(10.0, -0.01*(i-1000)) : uniform(engine));
        Real sn, cs;
        sineAndCosine(x, sn, cs);
        Real exactSine = (Real) std::sin((long double) x), exactCosine = (Real) std::cos((long double) x);
        if (x != 0)
            worstSine = std::max(worstSine, ulps(sn, exactSine));
        worstCosine = std::max(worstCosine, ulps(cs, exactCosine));
    }
}

} // namespace

TEST(Rotations, SmallAngleSineAndCosineAreTheLibrarysToRounding) {
    // A wrong coefficient (1/5040 as 1/5000) is ~1e4 ulps off at 0.1, a series one term short ~1e-2
    // ulps; rounding of the sum leaves at most 2.
    double worstSine, worstCosine;
    worstErrors<double>([] (double x, double& sn, double& cs) {BodyDynamics::sineAndCosine(x, sn, cs);}, worstSine, worstCosine);
    EXPECT_LE(worstSine, 2.0);
    EXPECT_LE(worstCosine, 2.0);
    double sn, cs;
    BodyDynamics::sineAndCosine(0.0, sn, cs);
    EXPECT_EQ(0.0, sn);
    EXPECT_EQ(1.0, cs);
}

TEST(Rotations, DeviceSineAndCosineAreTheLibrarysToRounding) {
    // In double, as on the host (a wrong coefficient, 1/720 as 1/700, is ~4e5 ulps off). In float
    // the series stop at x^5 and x^4: one term shorter they are 12 (sine) and 70 (cosine) ulps off
    // at 0.1, with a wrong coefficient (1/120 as 1/100) 3; their rounding in float leaves at most 1.
    double worstSine, worstCosine;
    worstErrors<double>([] (double x, double& sn, double& cs) {DeviceDouble::sineAndCosine(x, &sn, &cs);}, worstSine, worstCosine);
    std::cout << "double: sine " << worstSine << ", cosine " << worstCosine << " ulps" << std::endl;
    EXPECT_LE(worstSine, 2.0);
    EXPECT_LE(worstCosine, 2.0);
    worstErrors<float>([] (float x, float& sn, float& cs) {DeviceSingle::sineAndCosine(x, &sn, &cs);}, worstSine, worstCosine);
    std::cout << "single: sine " << worstSine << ", cosine " << worstCosine << " ulps" << std::endl;
    EXPECT_LE(worstSine, 1.0);
    EXPECT_LE(worstCosine, 1.0);
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

// ExactFlow turns the frame and, apart, the end velocities, in one interleaved pass
// (freeRotateFrameAndVectors): each must come out as its own freeRotate call gives it, bit for bit,
// at thermal and at large angles (the library's sine and cosine).
TEST(Rotations, InterleavedRotationsAreTheSeparateOnes) {
    BodyType type;
    type.numRotations = 3;
    type.inertia = Vec3(0.7, 1.3, 2.2);
    for (double scale : {0.05, 5.0}) {
        Vec3 frameDrive = Vec3(0.3, -0.2, 0.5)*scale;
        Vec3 vectors[3] = {Vec3(-0.4, 0.6, 0.1)*scale, Vec3(1, 2, 3), Vec3(-0.5, 0.1, 0.9)};  // the drive, then what it carries
        double q[3][3] = {{0.36, 0.48, -0.8}, {-0.8, 0.6, 0}, {0.48, 0.64, 0.6}};
        double separateQ[3][3];
        std::copy(&q[0][0], &q[0][0]+9, &separateQ[0][0]);
        Vec3 separateFrameDrive = frameDrive, separateVectors[3] = {vectors[0], vectors[1], vectors[2]};
        BodyDynamics::freeRotate(separateQ, type, 0.1, separateFrameDrive, nullptr, 0);
        BodyDynamics::freeRotate(nullptr, type, 0.1, separateVectors[0], separateVectors+1, 2);
        BodyDynamics::freeRotateFrameAndVectors(q, type, 0.1, frameDrive, vectors, 3);
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 3; k++) {
                EXPECT_EQ(separateQ[i][k], q[i][k]) << "scale " << scale;
                EXPECT_EQ(separateVectors[i][k], vectors[i][k]) << "scale " << scale << ", vector " << i;
            }
        for (int k = 0; k < 3; k++)
            EXPECT_EQ(separateFrameDrive[k], frameDrive[k]);
        // Both turned (at 0.05 by about 0.005 rad, in the small-angle series; at 5 by about 0.5).
        EXPECT_GT(std::abs(q[0][0]-0.36)+std::abs(q[1][1]-0.6), 1e-4*scale);
        EXPECT_GT(std::abs(vectors[1][0]-1), 1e-4*scale);
    }
}
