#ifndef RIGID_LANGEVIN_RESISTANCE_TEST_HELPERS_H_
#define RIGID_LANGEVIN_RESISTANCE_TEST_HELPERS_H_

// Small helpers shared by the TestResistanceTensor*.cpp files.

#include "openmm/OpenMMException.h"
#include "openmm/Vec3.h"
#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace ResistanceTestHelpers {

typedef Eigen::Matrix<double, 6, 6> Matrix6;

inline Matrix6 toMatrix6(const std::vector<double>& values) {
    return Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> >(values.data());
}

/** The distance between two points. */
inline double distance(const OpenMM::Vec3& a, const OpenMM::Vec3& b) {
    return std::sqrt((a-b).dot(a-b));
}

/** Largest element of |a - b| relative to the largest element of |b|. */
inline double relativeDifference(const Matrix6& a, const Matrix6& b) {
    return (a-b).cwiseAbs().maxCoeff()/b.cwiseAbs().maxCoeff();
}

/** A uniformly random proper rotation (QR of a Gaussian matrix, signs fixed). */
inline Eigen::Matrix3d randomRotation(std::mt19937& random) {
    std::normal_distribution<double> gauss;
    Eigen::Matrix3d g;
    for (int i = 0; i < 9; i++)
        g(i/3, i%3) = gauss(random);
    Eigen::HouseholderQR<Eigen::Matrix3d> qr(g);
    Eigen::Matrix3d q = qr.householderQ();
    Eigen::Matrix3d r = qr.matrixQR().triangularView<Eigen::Upper>();
    for (int i = 0; i < 3; i++)
        if (r(i, i) < 0)
            q.col(i) *= -1;
    if (q.determinant() < 0)
        q.col(0) *= -1;
    return q;
}

inline std::vector<double> rowMajor(const Eigen::Matrix3d& m) {
    std::vector<double> v(9);
    for (int i = 0; i < 9; i++)
        v[i] = m(i/3, i%3);
    return v;
}

/**
 * numBeads beads with radii in [0.1, 0.3] nm in a box, rejected until no two overlap (a gap of at
 * least minGap between surfaces).
 */
inline void randomBeads(int numBeads, double box, double minGap, std::mt19937& random,
                        std::vector<OpenMM::Vec3>& positions, std::vector<double>& radii) {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    positions.clear();
    radii.clear();
    while ((int) positions.size() < numBeads) {
        OpenMM::Vec3 p(box*uniform(random), box*uniform(random), box*uniform(random));
        double a = 0.1+0.2*uniform(random);
        bool fits = true;
        for (int i = 0; i < (int) positions.size(); i++) {
            OpenMM::Vec3 d = p-positions[i];
            if (std::sqrt(d.dot(d)) < a+radii[i]+minGap)
                fits = false;
        }
        if (fits) {
            positions.push_back(p);
            radii.push_back(a);
        }
    }
}

/** Run f, which must throw an OpenMMException whose message contains every one of the parts. */
template <class F>
void expectThrowMentioning(F f, const std::vector<std::string>& parts) {
    try {
        f();
        ADD_FAILURE() << "no exception was thrown";
    }
    catch (const OpenMM::OpenMMException& e) {
        std::string message = e.what();
        for (const std::string& part : parts)
            EXPECT_NE(std::string::npos, message.find(part)) << "the message \"" << message << "\" does not mention \"" << part << "\"";
    }
}

} // namespace ResistanceTestHelpers

#endif
