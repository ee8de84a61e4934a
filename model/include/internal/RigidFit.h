#ifndef RIGID_LANGEVIN_RIGID_FIT_H_
#define RIGID_LANGEVIN_RIGID_FIT_H_

#include "internal/ResistanceMath.h"
#include "openmm/Vec3.h"
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <vector>

namespace RigidLangevinPlugin {

/** A body rotation Q (BodyState::rotation) as a matrix. */
inline Eigen::Matrix3d toMatrix3(const double q[3][3]) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m(i, j) = q[i][j];
    return m;
}

inline void fromMatrix3(const Eigen::Matrix3d& m, double q[3][3]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            q[i][j] = m(i, j);
}

/**
 * Kabsch: the proper rotation A minimizing sum |A from_i - to_i|^2 over two centred point sets.
 * Returns the largest remaining distance |A from_i - to_i|, and in worst the point where it is.
 */
inline double fitRotation(const std::vector<OpenMM::Vec3>& from, const std::vector<OpenMM::Vec3>& to, Eigen::Matrix3d& a, int& worst) {
    using ResistanceMath::toEigen;
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    for (int i = 0; i < (int) from.size(); i++)
        h += toEigen(from[i])*toEigen(to[i]).transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = ((svd.matrixV()*svd.matrixU().transpose()).determinant() < 0 ? -1 : 1);
    a = svd.matrixV()*d*svd.matrixU().transpose();
    double deviation = 0;
    worst = 0;
    for (int i = 0; i < (int) from.size(); i++) {
        double dev = (a*toEigen(from[i])-toEigen(to[i])).norm();
        if (dev > deviation) {
            deviation = dev;
            worst = i;
        }
    }
    return deviation;
}

/** The largest distance between two of the points (once per body type: quadratic in its size). */
inline double shapeDiameter(const std::vector<OpenMM::Vec3>& coords) {
    double squared = 0;
    for (int i = 0; i < (int) coords.size(); i++)
        for (int j = i+1; j < (int) coords.size(); j++)
            squared = std::max(squared, (coords[i]-coords[j]).dot(coords[i]-coords[j]));
    return std::sqrt(squared);
}

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_RIGID_FIT_H_*/
