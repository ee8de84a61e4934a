// Blobs above a no-slip wall (RotnePragerBlake): the self-mobility against Swan & Brady's closed
// forms, the whole regularised M symmetric and positive definite where blobs overlap each other
// and cut the wall (and not without the regularisation), open space far from the wall, the
// matrix-free product against the dense matrix, refusals, and the coupled resistance above the
// wall by the dense path and by conjugate gradients on the matrix-free operator. The blocks
// themselves are checked against an independent numpy implementation of Blake's image system in
// tests/test_hydrodynamics_wall.py.

#include "CoupledResistance.h"
#include "ResistanceTestHelpers.h"
#include "internal/BlobMobility.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/KrylovSolvers.h"
#include "internal/RotnePragerBlake.h"
#include "internal/RotnePragerYamakawa.h"
#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <random>

using namespace RigidLangevinPlugin;
using namespace ResistanceTestHelpers;
using OpenMM::Vec3;
using std::vector;

namespace {

/** The whole 3N x 3N matrix of an operator, column by column from its products. */
Eigen::MatrixXd columns(int n, const KrylovSolvers::Operator& product) {
    Eigen::MatrixXd m(n, n);
    for (int j = 0; j < n; j++) {
        Eigen::VectorXd e = Eigen::VectorXd::Unit(n, j), column;
        product(e, column);
        m.col(j) = column;
    }
    return m;
}

/** The matrix-free regularised M above the wall z0, both triangles. */
Eigen::MatrixXd wallMatrix(const vector<Vec3>& positions, const vector<double>& radii, double z0) {
    return columns(3*positions.size(), [&] (const Eigen::VectorXd& in, Eigen::VectorXd& out) {
        RotnePragerBlake::mobilityProduct(positions, radii, z0, in, out);
    });
}

/** The same blocks without the regularisation: every blob where it is, however close to the wall. */
Eigen::MatrixXd unregularisedMatrix(const vector<Vec3>& positions, const vector<double>& radii, double z0) {
    const int n = positions.size();
    Eigen::MatrixXd m(3*n, 3*n);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double free[9], image[9];
            Vec3 d = positions[j]-positions[i];
            RotnePragerYamakawa::mobilityBlock(d[0], d[1], d[2], radii[i], radii[j], free);
            if (i == j)
                for (int k = 0; k < 9; k++)
                    free[k] = (k%4 == 0 ? RotnePragerYamakawa::selfMobility(radii[i]) : 0.0);
            RotnePragerBlake::imageBlock(-d[0], -d[1], positions[i][2]-z0, positions[j][2]-z0, radii[i], radii[j], image);
            for (int k = 0; k < 9; k++)
                m(3*i+k/3, 3*j+k%3) = free[k]+image[k];
        }
    return m;
}

/** numBlobs blobs of radii 0.2-0.3 nm crowded in a 1.5 nm square, at heights 0.02-0.8 nm above z0: many overlap, many cut the wall. */
void crowdNearWall(int numBlobs, double z0, std::mt19937& random, vector<Vec3>& positions, vector<double>& radii) {
    std::uniform_real_distribution<double> uniform(0, 1);
    positions.clear();
    radii.clear();
    for (int i = 0; i < numBlobs; i++) {
        positions.push_back(Vec3(1.5*uniform(random), 1.5*uniform(random), z0+0.02+0.78*uniform(random)));
        radii.push_back(0.2+0.1*uniform(random));
    }
}

} // namespace

TEST(RotnePragerBlake, SelfMobilityMatchesClosedForms) {
    // Swan & Brady's self-mobility at h/a = 2 and 4, exact fractions (shared notes: 0.732422,
    // 0.496094; 0.861267, 0.726440), from the closed form, from the general image block at i = j,
    // and from the matrix of one blob above a wall at z0 = 0.7.
    const double a = 0.3, z0 = 0.7, stokes = 1/(6*M_PI*a);
    const double expected[2][3] = {{2, 375.0/512, 127.0/256}, {4, 14111.0/16384, 5951.0/8192}};
    for (const auto& e : expected) {
        const double h = e[0]*a;
        double parallel, perpendicular, image[9];
        RotnePragerBlake::selfMobility(h, a, parallel, perpendicular);
        EXPECT_NEAR(parallel/stokes, e[1], 1e-12);
        EXPECT_NEAR(perpendicular/stokes, e[2], 1e-12);
        RotnePragerBlake::imageBlock(0, 0, h, h, a, a, image);
        EXPECT_NEAR(1+image[0]/stokes, e[1], 1e-12);
        EXPECT_NEAR(1+image[4]/stokes, e[1], 1e-12);
        EXPECT_NEAR(1+image[8]/stokes, e[2], 1e-12);
        for (int k : {1, 2, 3, 5, 6, 7})
            EXPECT_EQ(image[k], 0.0);
        Eigen::MatrixXd m = RotnePragerBlake::mobilityMatrix({Vec3(0.4, -1.0, z0+h)}, {a}, z0);
        EXPECT_NEAR(m(0, 0)/stokes, e[1], 1e-12);
        EXPECT_NEAR(m(2, 2)/stokes, e[2], 1e-12);
    }
}

TEST(RotnePragerBlake, SymmetricPositiveDefiniteNearTheWall) {
    // Ten crowds of 40 blobs of unequal radii, many overlapping and many closer to the wall than
    // their radius: the regularised M (both triangles from the product, which forms each block
    // on its own) is symmetric to rounding and positive definite. The same blocks without the
    // regularisation are not: the test can fail.
    std::mt19937 random(11);
    int indefiniteWithout = 0;
    for (int trial = 0; trial < 10; trial++) {
        vector<Vec3> positions;
        vector<double> radii;
        crowdNearWall(40, -0.4, random, positions, radii);
        Eigen::MatrixXd m = wallMatrix(positions, radii, -0.4);
        EXPECT_LT((m-m.transpose()).cwiseAbs().maxCoeff(), 1e-15*m.cwiseAbs().maxCoeff());
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5*(m+m.transpose()));
        EXPECT_GT(eigen.eigenvalues()[0], 1e-6*eigen.eigenvalues()[m.rows()-1]) << "trial " << trial;
        Eigen::MatrixXd raw = unregularisedMatrix(positions, radii, -0.4);
        if (Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5*(raw+raw.transpose())).eigenvalues()[0] < 0)
            indefiniteWithout++;
    }
    EXPECT_EQ(indefiniteWithout, 10);
}

TEST(RotnePragerBlake, MatrixFreeProductIsTheDenseMatrix) {
    // The dense lower triangle and the matrix-free product (rows on 3 "threads") agree to
    // rounding; HostBlobMobility gives the same whether it stores M or not.
    std::mt19937 random(5);
    vector<Vec3> positions;
    vector<double> radii;
    crowdNearWall(50, 0.25, random, positions, radii);
    KrylovSolvers::ParallelFor inThree = [] (int count, const std::function<void (int, int)>& task) {
        for (int part = 0; part < 3; part++)
            task(part*count/3, (part+1)*count/3);
    };
    Eigen::MatrixXd dense = RotnePragerBlake::mobilityMatrix(positions, radii, 0.25, inThree);
    Eigen::MatrixXd full = dense.selfadjointView<Eigen::Lower>();
    Eigen::VectorXd f = Eigen::VectorXd::Random(150), product;
    RotnePragerBlake::mobilityProduct(positions, radii, 0.25, f, product, inThree);
    EXPECT_LT((product-full*f).norm(), 1e-14*product.norm());
    HostBlobMobility stored(inThree), matrixFree(inThree, 0);
    stored.setWall(0.25);
    matrixFree.setWall(0.25);
    stored.setBlobs(positions, radii);
    matrixFree.setBlobs(positions, radii);
    Eigen::VectorXd fromStored, fromMatrixFree;
    stored.multiply(f, fromStored);
    matrixFree.multiply(f, fromMatrixFree);
    EXPECT_LT((fromStored-full*f).norm(), 1e-14*product.norm());
    EXPECT_LT((fromMatrixFree-full*f).norm(), 1e-14*product.norm());
}

TEST(RotnePragerBlake, FarFromTheWallIsOpenSpace) {
    // A wall 1e6 blob radii below: M differs from the unbounded one by the self term's leading
    // 9a/(16h) (5.6e-7 of it), so by about 1e-6 and no more.
    std::mt19937 random(7);
    vector<Vec3> positions;
    vector<double> radii;
    randomBeads(20, 2.0, -0.1, random, positions, radii);
    const double z0 = -0.25e6;
    Eigen::MatrixXd wall = RotnePragerBlake::mobilityMatrix(positions, radii, z0).selfadjointView<Eigen::Lower>();
    Eigen::MatrixXd open = CoupledResistanceMath::mobilityMatrix(positions, radii).selfadjointView<Eigen::Lower>();
    double worst = ((wall-open).cwiseAbs().array()/open.diagonal().maxCoeff()).maxCoeff();
    EXPECT_LT(worst, 1e-6);
    EXPECT_GT(worst, 1e-7);  // it does see the wall
}

TEST(RotnePragerBlake, RefusesBlobsAtOrBelowTheWall) {
    // A centre below or on the wall is refused naming the blob (by index, for the caller to map to
    // its body); CoupledResistance names the body and its blob; a wall with a periodic box is
    // refused; two equal blobs that the regularisation raises to the same sphere are refused.
    vector<Vec3> positions = {Vec3(0, 0, 1), Vec3(0.5, 0, 1), Vec3(1, 0, 0.2), Vec3(1.5, 0, 1)};
    vector<double> radii(4, 0.2);
    for (double z0 : {0.3, 0.2}) {
        try {
            RotnePragerBlake::validate("test", positions, radii, z0);
            ADD_FAILURE() << "a blob at or below the wall was accepted";
        }
        catch (const RotnePragerBlake::BlobBelowWallException& e) {
            EXPECT_EQ(e.getBlob(), 2);
            EXPECT_NE(std::string(e.what()).find("test: blob 2 has its centre at z = 0.2 nm, at or below the no-slip wall"), std::string::npos) << e.what();
        }
    }
    HostBlobMobility mobility;
    mobility.setWall(0.3);
    EXPECT_THROW(mobility.setBlobs(positions, radii), RotnePragerBlake::BlobBelowWallException);
    Vec3 box[3] = {Vec3(5, 0, 0), Vec3(0, 5, 0), Vec3(0, 0, 5)};
    expectThrowMentioning([&] () { mobility.setBlobs({Vec3(0, 0, 1)}, {0.2}, box); }, {"periodic box"});
    CoupledResistance coupled;
    coupled.addBody({positions[0], positions[1]}, {0.2, 0.2}, positions[0]);
    coupled.addBody({positions[2], positions[3]}, {0.2, 0.2}, positions[3]);
    coupled.setWall(0.25);
    expectThrowMentioning([&] () { coupled.getResistance(); }, {"CoupledResistance::getResistance: blob 0 of body 1 has its centre at z = 0.2 nm", "wall at z = 0.25 nm"});
    expectThrowMentioning([&] () { coupled.setPeriodicBox(box[0], box[1], box[2]); }, {"periodic box", "not supported"});
    CoupledResistance periodic;
    periodic.setPeriodicBox(box[0], box[1], box[2]);
    expectThrowMentioning([&] () { periodic.setWall(0); }, {"periodic box", "not supported"});
    expectThrowMentioning([&] () { RotnePragerBlake::validate("test", {Vec3(0, 0, 0.05), Vec3(0, 0, 0.15)}, {0.2, 0.2}, 0); },
                          {"blob 0 and blob 1", "same sphere"});
    RotnePragerBlake::validate("test", {Vec3(0, 0, 0.05), Vec3(0, 0, 0.15)}, {0.2, 0.25}, 0);  // unequal: distinct when raised
}

TEST(RotnePragerBlake, CoupledResistanceAboveTheWall) {
    // Two bodies of 5 blobs, one cutting the wall: R above the wall is symmetric positive definite
    // and differs from the unbounded one; the same R from conjugate gradients on the matrix-free
    // operator (HostBlobMobility, 6 columns per body) agrees to the solver's tolerance; and with
    // the wall 1e6 radii below, R is the unbounded one to ~1e-6.
    std::mt19937 random(2);
    vector<Vec3> blobs[2];
    vector<double> radii[2];
    vector<Vec3> all;
    vector<double> allRadii;
    for (int b = 0; b < 2; b++) {
        randomBeads(5, 0.8, 0.02, random, blobs[b], radii[b]);
        for (Vec3& p : blobs[b])
            p += Vec3(0.9*b, 0, 0.05);
        all.insert(all.end(), blobs[b].begin(), blobs[b].end());
        allRadii.insert(allRadii.end(), radii[b].begin(), radii[b].end());
    }
    auto resistance = [&] (double z0, bool wall) {
        CoupledResistance coupled;
        for (int b = 0; b < 2; b++)
            coupled.addBody(blobs[b], radii[b], blobs[b][0]);
        if (wall)
            coupled.setWall(z0);
        return Eigen::MatrixXd(Eigen::Map<const Eigen::Matrix<double, 12, 12, Eigen::RowMajor> >(coupled.getResistance().data()));
    };
    Eigen::MatrixXd r = resistance(0, true), open = resistance(0, false);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(r).eigenvalues()[0], 0);
    EXPECT_GT((r-open).cwiseAbs().maxCoeff(), 0.1*open.cwiseAbs().maxCoeff());
    // Conjugate gradients, unpreconditioned, on the matrix-free operator: R = K^T M^-1 K column by column.
    HostBlobMobility mobility(KrylovSolvers::sequentially, 0);
    mobility.setWall(0);
    mobility.setBlobs(all, allRadii);
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(30, 12);
    for (int i = 0; i < 10; i++) {
        Vec3 arm = all[i]-blobs[i/5][0];
        k.block<3, 3>(3*i, 6*(i/5)).setIdentity();
        k.block<3, 3>(3*i, 6*(i/5)+3) << 0, arm[2], -arm[1], -arm[2], 0, arm[0], arm[1], -arm[0], 0;
    }
    Eigen::MatrixXd krylov(12, 12);
    KrylovSolvers::Operator product = [&] (const Eigen::VectorXd& in, Eigen::VectorXd& out) { mobility.multiply(in, out); };
    KrylovSolvers::Operator identity = [] (const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = in; };
    for (int c = 0; c < 12; c++) {
        Eigen::VectorXd x;
        KrylovSolvers::Result result = KrylovSolvers::conjugateGradient(product, identity, k.col(c), x, 1e-12, 300);
        EXPECT_EQ(result.outcome, KrylovSolvers::Converged) << KrylovSolvers::explain(result);
        krylov.col(c) = k.transpose()*x;
    }
    EXPECT_LT((krylov-r).cwiseAbs().maxCoeff(), 1e-9*r.cwiseAbs().maxCoeff());
    double far = (resistance(-0.25e6, true)-open).cwiseAbs().maxCoeff()/open.cwiseAbs().maxCoeff();
    EXPECT_LT(far, 3e-6);
    EXPECT_GT(far, 1e-8);
}
