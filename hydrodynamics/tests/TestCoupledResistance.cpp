// CoupledResistance: bodies made of blobs that feel each other through the solvent, against exact
// answers: one body is its own bead tensor, single blobs are the RPY mobility inverted, far bodies
// decouple, and two resolved spheres converge to Jeffrey & Onishi's resistance functions.

#include "CoupledResistance.h"
#include "ResistanceTensor.h"
#include "ResistanceTestHelpers.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/RotnePragerYamakawa.h"
#include "internal/ShellModel.h"
#include "openmm/OpenMMException.h"
#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <cstdlib>
#include <random>
#include <string>

using namespace RigidLangevinPlugin;
using namespace ResistanceTestHelpers;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

typedef Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Matrix;

Matrix toMatrix(const vector<double>& values, int n) {
    return Eigen::Map<const Matrix>(values.data(), n, n);
}

/** A few blobs of a rigid body (not on a line), placed about centre. */
void someBody(std::mt19937& random, const Vec3& centre, vector<Vec3>& positions, vector<double>& radii) {
    randomBeads(5, 0.8, 0.02, random, positions, radii);
    for (Vec3& p : positions)
        p += centre;
}

} // namespace

TEST(CoupledResistance, OneBodyIsItsBeadTensor) {
    // With one body, R is ResistanceTensor::beads() of its blobs (no volume correction), about the
    // same point; and the mobility is its inverse.
    std::mt19937 random(3);
    vector<Vec3> positions;
    vector<double> radii;
    someBody(random, Vec3(0.3, -0.2, 0.5), positions, radii);
    Vec3 origin(0.1, 0.7, -0.3);
    CoupledResistance coupled;
    EXPECT_EQ(coupled.addBody(positions, radii, origin), 0);
    Matrix6 r = toMatrix(coupled.getResistance(), 6);
    Matrix6 beads = toMatrix6(ResistanceTensor::beads(positions, radii).getMatrix(origin));
    EXPECT_LT(relativeDifference(r, beads), 1e-12);
    Matrix6 mobility = toMatrix(coupled.getMobility(), 6);
    EXPECT_LT((mobility*r-Matrix6::Identity()).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(CoupledResistance, SingleBlobsInvertTheirMobility) {
    // Three bodies of one blob each, unequal radii, one pair overlapping: the translational blocks of
    // R are the inverse of the blobs' 9x9 generalised RPY mobility (written here from the formula's
    // blocks), and rotation has no friction; getMobility() refuses, naming a body.
    vector<Vec3> centres = {Vec3(0, 0, 0), Vec3(0.5, 0.1, 0), Vec3(0.55, 0.25, 0.1)};
    vector<double> radii = {0.2, 0.15, 0.1};
    CoupledResistance coupled;
    for (int i = 0; i < 3; i++)
        coupled.addBody({centres[i]}, {radii[i]}, centres[i]);
    Matrix r = toMatrix(coupled.getResistance(), 18);
    Eigen::MatrixXd m(9, 9);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double block[9];
            Vec3 d = centres[j]-centres[i];
            if (i == j)
                for (int k = 0; k < 9; k++)
                    block[k] = (k % 4 == 0 ? RotnePragerYamakawa::selfMobility(radii[i]) : 0.0);
            else
                RotnePragerYamakawa::mobilityBlock(d[0], d[1], d[2], radii[i], radii[j], block);
            for (int k = 0; k < 9; k++)
                m(3*i+k/3, 3*j+k%3) = block[k];
        }
    Eigen::MatrixXd inverse = m.inverse();
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            EXPECT_LT((r.block(6*i, 6*j, 3, 3)-inverse.block(3*i, 3*j, 3, 3)).cwiseAbs().maxCoeff(), 1e-12*inverse.cwiseAbs().maxCoeff());
            EXPECT_LT(r.block(6*i+3, 6*j+3, 3, 3).cwiseAbs().maxCoeff(), 1e-14*inverse.cwiseAbs().maxCoeff());
        }
    try {
        coupled.getMobility();
        FAIL() << "the mobility of bodies that cannot rotate was returned";
    }
    catch (const OpenMMException& e) {
        EXPECT_NE(std::string(e.what()).find("body 0 has no friction for some rotation"), std::string::npos) << e.what();
    }
}

TEST(CoupledResistance, BodiesFarApartDecouple) {
    // Two bodies of size ~0.5 nm 1000 nm apart: the coupling blocks are of order size/distance
    // (5e-4 here) and each diagonal block is the body's own tensor to the square of that.
    std::mt19937 random(5);
    vector<Vec3> p1, p2;
    vector<double> r1, r2;
    someBody(random, Vec3(), p1, r1);
    someBody(random, Vec3(1000, 0, 0), p2, r2);
    CoupledResistance coupled;
    coupled.addBody(p1, r1, p1[0]);
    coupled.addBody(p2, r2, p2[0]);
    Matrix r = toMatrix(coupled.getResistance(), 12);
    Matrix6 own1 = toMatrix6(ResistanceTensor::beads(p1, r1).getMatrix(p1[0]));
    Matrix6 own2 = toMatrix6(ResistanceTensor::beads(p2, r2).getMatrix(p2[0]));
    for (double difference : {relativeDifference(r.block<6, 6>(0, 0), own1), relativeDifference(r.block<6, 6>(6, 6), own2)}) {
        EXPECT_LT(difference, 3e-6);
        EXPECT_GT(difference, 1e-9);  // they do feel each other
    }
    double coupling = r.block(0, 6, 6, 6).cwiseAbs().maxCoeff()/own1.cwiseAbs().maxCoeff();
    EXPECT_LT(coupling, 3e-3);
    EXPECT_GT(coupling, 1e-5);
    EXPECT_LT((r-r.transpose()).cwiseAbs().maxCoeff(), 1e-15*r.cwiseAbs().maxCoeff());
}

namespace {

/** Jeffrey & Onishi's resistance functions of two equal spheres 4 radii apart (see below). */
struct ResistanceFunctions {
    double value[8];
};
const char* FunctionNames[8] = {"X11A", "Y11A", "X12A", "Y12A", "X11C", "Y11C", "Y11B", "Y12B"};
const double JeffreyOnishi4[8] = {1.16947, 1.04330, -0.42721, -0.20448, 1.33373, 1.33896, 0.013554, -0.065435};

/**
 * Two spheres of radius a, centres 4a apart along x, each a rough shell of blobs of radius sigma
 * on its surface (as ResistanceTensor::roughShell tiles it), at six sigmas from the one that gives
 * about maxBeads blobs a sphere to twice that; every element of the 12x12 resistance extrapolated
 * linearly to sigma = 0, as shellExtrapolated() does for one body. Returns the functions in the
 * scaling A by 6 pi a, B by 6 pi a^2, C by 6 pi a^3, and checks the structure the pair's symmetry
 * demands: R21 = R12^T, and the two B couplings (torque_z from v_y of the same sphere and of the
 * other) of opposite signs.
 */
ResistanceFunctions twoSpheres(int maxBeads) {
    const double a = 0.5;
    Vec3 c1(0, 0, 0), c2(4*a, 0, 0);
    ShellModel::Tiling sphere = [&](double sigma) { return ShellModel::tileSpheroid(a, a, sigma); };
    vector<double> sigmas = ShellModel::beadRadii(sphere, 4*M_PI*a*a, maxBeads, 6);
    vector<Matrix6> blocks[3];  // 11, 12, 21
    for (double sigma : sigmas) {
        vector<Vec3> shell = sphere(sigma), s1, s2;
        for (const Vec3& p : shell) {
            s1.push_back(c1+p);
            s2.push_back(c2+p);
        }
        vector<double> radii(shell.size(), sigma);
        CoupledResistance coupled;
        coupled.addBody(s1, radii, c1);
        coupled.addBody(s2, radii, c2);
        Matrix r = toMatrix(coupled.getResistance(), 12);
        blocks[0].push_back(r.block<6, 6>(0, 0));
        blocks[1].push_back(r.block<6, 6>(0, 6));
        blocks[2].push_back(r.block<6, 6>(6, 0));
    }
    Matrix6 r11 = ShellModel::extrapolateToZeroBeadSize(sigmas, blocks[0]);
    Matrix6 r12 = ShellModel::extrapolateToZeroBeadSize(sigmas, blocks[1]);
    EXPECT_LT((ShellModel::extrapolateToZeroBeadSize(sigmas, blocks[2])-r12.transpose()).cwiseAbs().maxCoeff(), 1e-10*r11.cwiseAbs().maxCoeff());
    EXPECT_LT(r11(5, 1)*r12(5, 1), 0);
    const double A = 6*M_PI*a, B = 6*M_PI*a*a, C = 6*M_PI*a*a*a;
    return {{r11(0, 0)/A, r11(1, 1)/A, r12(0, 0)/A, r12(1, 1)/A, r11(3, 3)/C, r11(4, 4)/C, std::abs(r11(5, 1))/B, -std::abs(r12(5, 1))/B}};
}

} // namespace

TEST(CoupledResistance, TwoSpheresConvergeToJeffreyOnishi) {
    // Jeffrey & Onishi (J. Fluid Mech. 139, 261 (1984)) at r/a = 4, in the scaling above: X11A
    // 1.16947, Y11A 1.04330, X12A -0.42721, Y12A -0.20448, X11C 1.33373, Y11C 1.33896, Y11B
    // 0.013554, Y12B -0.065435. With 600 blobs a sphere at the finest every function is within 0.7%
    // (1.2% for the small Y11B; measured 0.06-1.1%), and each is closer than with 300 (where they are
    // 0.8-4% off): the blob model converges to the exact pair. (At 1200 they are within 0.3%.)
    ResistanceFunctions coarse = twoSpheres(300), fine = twoSpheres(600);
    for (int k = 0; k < 8; k++) {
        double exact = JeffreyOnishi4[k];
        EXPECT_NEAR(fine.value[k], exact, (k == 6 ? 0.012 : 0.007)*std::abs(exact)) << FunctionNames[k];
        EXPECT_LT(std::abs(fine.value[k]-exact), std::abs(coarse.value[k]-exact)) << FunctionNames[k];
    }
    // Two spheres settling in line under equal forces (no rotation, by symmetry) move at
    // 1/(X11A + X12A) = 1.34724 times a lone sphere's speed (Stimson & Jeffery's problem, here from
    // Jeffrey & Onishi's functions): within 0.5% at 600 blobs a sphere, closer than at 300.
    const double exactSettling = 1/(JeffreyOnishi4[0]+JeffreyOnishi4[2]);
    EXPECT_NEAR(exactSettling, 1.34724, 1e-5);
    double fineSettling = 1/(fine.value[0]+fine.value[2]), coarseSettling = 1/(coarse.value[0]+coarse.value[2]);
    EXPECT_NEAR(fineSettling, exactSettling, 0.005*exactSettling);
    EXPECT_LT(std::abs(fineSettling-exactSettling), std::abs(coarseSettling-exactSettling));
}

TEST(CoupledResistance, BlobsScaledToTheirBodysFrictionCoupleByOseen) {
    // Far apart (r = 500 a), two calibrated spheres couple by the Oseen tensor (I + rr)/(8 pi r)
    // times the ratio of their blobs' friction to their own: a rough shell on the surface (sigma =
    // a/10) over-resists by about 2.7%, and so does its coupling. Scaled to the sphere's friction
    // (ResistanceTensor::scaleBlobsToFriction), the shell sits just inside the surface and the
    // coupling is Oseen's to the far field's own (a/r)^2 terms.
    const double a = 0.5, sigma = 0.05, r = 500*a;
    const Vec3 c1(0.1, -0.2, 0.3), c2 = c1+Vec3(r, 0, 0);
    vector<Vec3> shell = ResistanceTensor::roughShellBeads({c1}, {a}, sigma);
    vector<double> radii(shell.size(), sigma);
    vector<Vec3> scaled = ResistanceTensor::scaleBlobsToFriction(shell, radii, c1, ResistanceTensor::sphere(a, c1));
    auto translationalTrace = [&](const vector<Vec3>& blobs, const vector<double>& blobRadii) {
        return toMatrix6(ResistanceTensor::beads(blobs, blobRadii).getMatrix(c1)).topLeftCorner(3, 3).trace();
    };
    EXPECT_NEAR(translationalTrace(scaled, radii), 18*M_PI*a, 1e-10*18*M_PI*a);
    for (int i = 0; i < (int) shell.size(); i++)
        EXPECT_NEAR(distance(scaled[i], c1), 0.972*distance(shell[i], c1), 0.002*a);  // measured 0.9722
    auto couplingOverOseen = [&](const vector<Vec3>& blobs) {
        vector<Vec3> moved;
        for (const Vec3& p : blobs)
            moved.push_back(p+c2-c1);
        CoupledResistance coupled;
        coupled.addBody(blobs, radii, c1);
        coupled.addBody(moved, radii, c2);
        coupled.setBodyResistance(0, ResistanceTensor::sphere(a, c1));
        coupled.setBodyResistance(1, ResistanceTensor::sphere(a, c2));
        Matrix mobility = toMatrix(coupled.getMobility(), 12);
        return Eigen::Vector3d(mobility(0, 6)*4*M_PI*r, mobility(1, 7)*8*M_PI*r, mobility(2, 8)*8*M_PI*r);
    };
    Eigen::Vector3d surface = couplingOverOseen(shell), inside = couplingOverOseen(scaled);
    for (int k = 0; k < 3; k++) {
        EXPECT_GT(surface[k]-1, 0.02);
        EXPECT_NEAR(inside[k], 1, 2e-3);  // the tiling's own anisotropy: 1.0010, 0.9995, 0.9995
    }
    EXPECT_NEAR(inside.mean(), 1, 2e-4);  // the trace is matched
    // Blobs too small spread out; a lone blob cannot change its friction and is refused, as are blobs
    // that over-resist even drawn in, and a centre that is not finite.
    vector<Vec3> small = {c1+Vec3(0.2, 0, 0), c1+Vec3(-0.1, 0.17, 0), c1+Vec3(-0.1, -0.17, 0), c1+Vec3(0, 0, 0.2)};
    vector<double> smallRadii(4, 0.15);
    vector<Vec3> spread = ResistanceTensor::scaleBlobsToFriction(small, smallRadii, c1, ResistanceTensor::sphere(a, c1));
    EXPECT_GT(distance(spread[0], c1), 1.2*distance(small[0], c1));
    EXPECT_NEAR(translationalTrace(spread, smallRadii), 18*M_PI*a, 1e-10*18*M_PI*a);
    expectThrowMentioning([&] { ResistanceTensor::scaleBlobsToFriction({c1}, {0.01}, c1, ResistanceTensor::sphere(a, c1)); },
                          {"less than the target", "larger"});
    expectThrowMentioning([&] { ResistanceTensor::scaleBlobsToFriction({c1}, {0.8}, c1, ResistanceTensor::sphere(a, c1)); },
                          {"more than the target", "smaller"});
    expectThrowMentioning([&] { ResistanceTensor::scaleBlobsToFriction(shell, radii, Vec3(std::nan(""), 0, 0), ResistanceTensor::sphere(a)); },
                          {"centre"});
    expectThrowMentioning([&] { ResistanceTensor::scaleBlobsToFriction(shell, {sigma}, c1, ResistanceTensor::sphere(a)); }, {"scaleBlobsToFriction"});
}

TEST(CoupledResistance, RejectsBadInput) {
    CoupledResistance coupled;
    EXPECT_THROW(coupled.getResistance(), OpenMMException);
    EXPECT_THROW(coupled.addBody({Vec3(0, 0, 0)}, {0.0}, Vec3()), OpenMMException);
    EXPECT_THROW(coupled.addBody({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {0.1}, Vec3()), OpenMMException);
    EXPECT_THROW(coupled.addBody({Vec3(0, 0, 0)}, {0.1}, Vec3(std::nan(""), 0, 0)), OpenMMException);
    // The same sphere in two bodies makes M singular: refused, naming both blobs by body.
    coupled.addBody({Vec3(0, 0, 0), Vec3(0.3, 0, 0), Vec3(0, 0.3, 0)}, {0.1, 0.1, 0.1}, Vec3());
    coupled.addBody({Vec3(1, 0, 0), Vec3(0.3, 0, 0), Vec3(1, 0.3, 0)}, {0.1, 0.1, 0.1}, Vec3(1, 0, 0));
    expectThrowMentioning([&] { coupled.getResistance(); }, {"blob 1 of body 0 and blob 1 of body 1", "coincident"});
}

TEST(CoupledResistance, RefusesBlobsTooLargeForThePeriodicBox) {
    // A blob's diameter must be under half the box's smallest width, the least distance between
    // opposite faces: here, in a triclinic box, 1.7698 nm (the planes of a and of b), less than any of
    // its vectors' components (2, 2, 1.9). Blobs of radius 0.44 nm pass, 0.45 nm are refused, naming
    // the blob and what to change; without the rule both give a resistance.
    const Vec3 box[3] = {Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(1, 1, 1.9)};
    const Vec3 normal = box[1].cross(box[2]);
    const double width = box[0].dot(normal)/std::sqrt(normal.dot(normal));
    ASSERT_NEAR(width, 1.7698, 1e-4);
    auto coupled = [&] (double radius) {
        CoupledResistance c;
        c.setPeriodicBox(box[0], box[1], box[2]);
        c.addBody({Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 0.5, 0)}, {0.1, 0.1, 0.1}, Vec3());
        c.addBody({Vec3(1, 1, 0.2), Vec3(1, 1, 0.7), Vec3(1.5, 1, 0.2)}, {0.1, radius, 0.1}, Vec3(1, 1, 0.2));
        return c.getResistance();
    };
    ASSERT_LT(2*0.44, width/2);
    EXPECT_NO_THROW(coupled(0.44));
    ASSERT_GT(2*0.45, width/2);
    expectThrowMentioning([&] { coupled(0.45); }, {"CoupledResistance::getResistance", "blob 1 of body 1", "radius 0.45 nm",
                                                   "half the box's smallest width (0.88", "larger box", "smaller blobs"});
}

TEST(CoupledResistance, RefusesTheSameSphereThroughThePeriodicBox) {
    // Blobs a box vector apart are one sphere in the box: M is singular. Refused, naming both, for
    // a shift by vectors of a triclinic box, and for blobs on opposite faces of it (keys just above 0
    // and just below the box's width along a's planes, the two ends of the sorted scan); blobs a
    // little further apart pass.
    const Vec3 box[3] = {Vec3(2, 0, 0), Vec3(0.3, 1.9, 0), Vec3(-0.2, 0.4, 2.1)};
    auto coupled = [&] (const Vec3& first, const Vec3& second) {
        CoupledResistance c;
        c.setPeriodicBox(box[0], box[1], box[2]);
        c.addBody({first, Vec3(0.5, 0.6, 0.7), Vec3(0.5, 0.9, 0.7)}, {0.1, 0.1, 0.1}, first);
        c.addBody({Vec3(1.2, 1, 1), Vec3(1.2, 1.3, 1), second}, {0.1, 0.1, 0.1}, Vec3(1.2, 1, 1));
        return c.getResistance();
    };
    const Vec3 p(0.1, 0.2, 0.3);
    expectThrowMentioning([&] { coupled(p, p+box[0]*2-box[2]+box[1]); }, {"blob 0 of body 0 and blob 2 of body 1", "same sphere through the periodic box"});
    EXPECT_NO_THROW(coupled(p, p+box[0]*2-box[2]+box[1]+Vec3(0.05, 0, 0)));
    // On the plane of b and c through the origin: a's fractional coordinate is 5e-14 and 1 - 5e-14.
    expectThrowMentioning([&] { coupled(Vec3(1e-13, 1, 1.26), Vec3(2-1e-13, 1, 1.26)); }, {"blob 0 of body 0 and blob 2 of body 1", "same sphere"});
    expectThrowMentioning([&] { coupled(Vec3(2-1e-13, 1, 1.26), Vec3(1e-13, 1, 1.26)); }, {"blob 0 of body 0 and blob 2 of body 1", "same sphere"});
}

TEST(CoupledResistance, CalibrationGivesALoneBodyItsOwnTensor) {
    // setBodyResistance(): alone, a body has exactly its own tensor (here an ellipsoid's, which its
    // five blobs resemble only roughly); calibrating to its blobs' own bead tensor changes nothing
    // (T = I); far apart, each calibrated body is its own tensor to the coupling's square; and the
    // calibrated R is T^T R T with T D T = Xi, T written here from eigendecompositions.
    std::mt19937 random(7);
    vector<Vec3> p1, p2;
    vector<double> r1, r2;
    someBody(random, Vec3(0.2, 0.1, -0.3), p1, r1);
    someBody(random, Vec3(1.1, 0.4, 0.2), p2, r2);
    ResistanceTensor own1 = ResistanceTensor::ellipsoid(0.5, 0.3, 0.2, p1[1]).rotated({0, 1, 0, -1, 0, 0, 0, 0, 1});
    ResistanceTensor own2 = ResistanceTensor::ellipsoid(0.4, 0.35, 0.25, p2[2]);
    Matrix6 xi1 = toMatrix6(own1.getMatrix(p1[0]));

    CoupledResistance alone;
    alone.addBody(p1, r1, p1[0]);
    alone.setBodyResistance(0, own1);
    EXPECT_LT(relativeDifference(toMatrix(alone.getResistance(), 6), xi1), 1e-12);

    CoupledResistance plain, same, calibrated;
    for (CoupledResistance* c : {&plain, &same, &calibrated}) {
        c->addBody(p1, r1, p1[0]);
        c->addBody(p2, r2, p2[0]);
    }
    same.setBodyResistance(0, ResistanceTensor::beads(p1, r1));
    same.setBodyResistance(1, ResistanceTensor::beads(p2, r2));
    calibrated.setBodyResistance(0, own1);
    calibrated.setBodyResistance(1, own2);
    Matrix r = toMatrix(plain.getResistance(), 12);
    EXPECT_LT((toMatrix(same.getResistance(), 12)-r).cwiseAbs().maxCoeff(), 1e-10*r.cwiseAbs().maxCoeff());

    auto power = [](const Matrix6& m, double exponent) {
        Eigen::SelfAdjointEigenSolver<Matrix6> eigen(m);
        return Matrix6(eigen.eigenvectors()*eigen.eigenvalues().array().pow(exponent).matrix().asDiagonal()*eigen.eigenvectors().transpose());
    };
    Matrix t = Matrix::Zero(12, 12);
    Matrix6 own[2] = {xi1, toMatrix6(own2.getMatrix(p2[0]))};
    vector<Vec3>* blobs[2] = {&p1, &p2};
    vector<double>* radii[2] = {&r1, &r2};
    for (int b = 0; b < 2; b++) {
        Matrix6 d = toMatrix6(ResistanceTensor::beads(*blobs[b], *radii[b]).getMatrix((*blobs[b])[0]));
        Matrix6 half = power(d, 0.5), inverseHalf = power(d, -0.5);
        t.block<6, 6>(6*b, 6*b) = inverseHalf*power(half*own[b]*half, 0.5)*inverseHalf;
        EXPECT_LT(relativeDifference(Matrix6(t.block<6, 6>(6*b, 6*b)*d*t.block<6, 6>(6*b, 6*b)), own[b]), 1e-10);
    }
    Matrix expected = t.transpose()*r*t;
    EXPECT_LT((toMatrix(calibrated.getResistance(), 12)-expected).cwiseAbs().maxCoeff(), 1e-10*expected.cwiseAbs().maxCoeff());
    EXPECT_GT(relativeDifference(Matrix6(expected.block<6, 6>(0, 0)), xi1), 0.01);  // close bodies change each other's friction

    CoupledResistance far;
    far.addBody(p1, r1, p1[0]);
    vector<Vec3> distant = p2;
    for (Vec3& p : distant)
        p += Vec3(1000, 0, 0);
    far.addBody(distant, r2, distant[0]);
    far.setBodyResistance(0, own1);
    Matrix farR = toMatrix(far.getResistance(), 12);
    double difference = relativeDifference(Matrix6(farR.block<6, 6>(0, 0)), xi1);
    EXPECT_LT(difference, 3e-6);
    EXPECT_GT(difference, 1e-9);

    // A body of one blob cannot be calibrated to a body that turns: refused, naming it.
    CoupledResistance single;
    single.addBody(p1, r1, p1[0]);
    single.addBody({Vec3(3, 0, 0)}, {0.2}, Vec3(3, 0, 0));
    single.setBodyResistance(1, ResistanceTensor::sphere(0.2, Vec3(3, 0, 0)));
    try {
        single.getResistance();
        FAIL() << "a one-blob body was calibrated";
    }
    catch (const OpenMMException& e) {
        EXPECT_NE(std::string(e.what()).find("body 1"), std::string::npos) << e.what();
    }
}

TEST(CoupledResistance, IsTheSameOnAnyNumberOfThreads) {
    // From 200 blobs the resistance runs on OPENMM_CPU_THREADS threads (M, its blocked Cholesky
    // factorisation, the solve for K and R in parts fixed by the sizes alone): 1, 2 and 3 threads
    // give the same bits, and they are Eigen's unblocked LLT's R (K^T M^-1 K) to rounding (a part
    // left out or counted twice, or a band's rows skipped wrongly, changes R by far more).
    std::mt19937 random(4);
    std::uniform_real_distribution<double> uniform(0, 1);
    vector<Vec3> positions;
    vector<double> radii;
    vector<int> owner;
    vector<Vec3> origins;
    for (int b = 0; b < 30; b++) {
        const Vec3 centre(4*uniform(random), 4*uniform(random), 4*uniform(random));
        origins.push_back(centre);
        for (int k = 0; k < 8; k++) {
            positions.push_back(centre+Vec3(0.3*(k%2), 0.3*((k/2)%2), 0.3*(k/4)));
            radii.push_back(0.15+0.05*uniform(random));
            owner.push_back(b);
        }
    }
    const char* saved = std::getenv("OPENMM_CPU_THREADS");
    const std::string previous = (saved == nullptr ? "" : saved);
    vector<Eigen::MatrixXd> results;
    for (const char* threads : {"1", "2", "3"}) {
        setenv("OPENMM_CPU_THREADS", threads, 1);
        results.push_back(CoupledResistanceMath::resistance("test", positions, radii, owner, origins));
    }
    if (saved == nullptr)
        unsetenv("OPENMM_CPU_THREADS");
    else
        setenv("OPENMM_CPU_THREADS", previous.c_str(), 1);
    for (int t = 1; t < 3; t++)
        for (int i = 0; i < results[0].size(); i++)
            ASSERT_EQ(results[0].data()[i], results[t].data()[i]) << t+1 << " threads, entry " << i;
    Eigen::MatrixXd m = CoupledResistanceMath::mobilityMatrix(positions, radii).selfadjointView<Eigen::Lower>();
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(3*positions.size(), 6*origins.size());
    for (int i = 0; i < (int) positions.size(); i++) {
        const Vec3 d = positions[i]-origins[owner[i]];
        Eigen::Matrix3d skew;
        skew << 0, -d[2], d[1], d[2], 0, -d[0], -d[1], d[0], 0;
        k.block<3, 3>(3*i, 6*owner[i]) = Eigen::Matrix3d::Identity();
        k.block<3, 3>(3*i, 6*owner[i]+3) = -skew;
    }
    Eigen::MatrixXd exact = k.transpose()*m.llt().solve(k);
    EXPECT_LT((results[0]-exact).norm(), 1e-12*exact.norm());
}
