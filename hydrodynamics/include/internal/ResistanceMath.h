#ifndef RIGID_LANGEVIN_RESISTANCE_MATH_H_
#define RIGID_LANGEVIN_RESISTANCE_MATH_H_

#include "openmm/Vec3.h"
#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace RigidLangevinPlugin {

/**
 * Small dense-algebra helpers for 6x6 resistance tensors in the convention of ResistanceTensor:
 * (force, torque) = -viscosity * Xi * (velocity, angular velocity).
 */
namespace ResistanceMath {

typedef Eigen::Matrix<double, 6, 6> Matrix6;

/** The matrix of the cross product: skew(r)*x = r x x. */
inline Eigen::Matrix3d skew(const Eigen::Vector3d& r) {
    Eigen::Matrix3d s;
    s << 0, -r[2], r[1],
         r[2], 0, -r[0],
         -r[1], r[0], 0;
    return s;
}

inline Eigen::Vector3d toEigen(const OpenMM::Vec3& v) {
    return Eigen::Vector3d(v[0], v[1], v[2]);
}

inline OpenMM::Vec3 toVec3(const Eigen::Vector3d& v) {
    return OpenMM::Vec3(v[0], v[1], v[2]);
}

/**
 * Move the reference point of a tensor from O to P, where rOP = P - O. The velocity of O is
 * v_O = v_P + rOP x omega and the torque about P is torque_O - rOP x force, so with
 * A = [[1, skew(rOP)], [0, 1]] the tensor about P is A^T Xi_O A: a congruence, which keeps it
 * symmetric positive definite.
 */
inline Matrix6 moveOrigin(const Matrix6& xi, const Eigen::Vector3d& rOP) {
    Matrix6 a = Matrix6::Identity();
    a.block<3, 3>(0, 3) = skew(rOP);
    return a.transpose()*xi*a;
}

/** Express a tensor in a rotated frame: vectors transform as x' = R x. */
inline Matrix6 rotate(const Matrix6& xi, const Eigen::Matrix3d& rotation) {
    Matrix6 r = Matrix6::Zero();
    r.block<3, 3>(0, 0) = rotation;
    r.block<3, 3>(3, 3) = rotation;
    return r*xi*r.transpose();
}

/**
 * The centre of resistance relative to the tensor's origin: the point where the coupling block is
 * symmetric. Moving the origin by r changes the torque-from-velocity block by -skew(r)*Xtt, so its
 * antisymmetric part vanishes where (tr(Xtt) 1 - Xtt) r equals the axial vector of that part.
 */
inline Eigen::Vector3d centerOfResistance(const Matrix6& xi) {
    Eigen::Matrix3d tt = xi.block<3, 3>(0, 0);
    Eigen::Matrix3d rt = xi.block<3, 3>(3, 0);
    Eigen::Vector3d axial(rt(2, 1)-rt(1, 2), rt(0, 2)-rt(2, 0), rt(1, 0)-rt(0, 1));
    Eigen::Matrix3d a = tt.trace()*Eigen::Matrix3d::Identity()-tt;
    return a.ldlt().solve(axial);
}

/**
 * The centre of diffusion relative to the tensor's origin: the point where the coupling block of the
 * diffusion tensor D ~ Xi^-1 is symmetric. Moving the origin by r takes the block giving angular
 * velocity from force, Drt, to Drt + Drr skew(r) (D transforms with the inverse of the congruence
 * that moves Xi), whose antisymmetric part vanishes where (tr(Drr) 1 - Drr) r equals minus the
 * axial vector of Drt's. The overall scale of D (kT, viscosity) drops out.
 */
inline Eigen::Vector3d centerOfDiffusion(const Matrix6& xi) {
    Matrix6 d = xi.llt().solve(Matrix6::Identity());
    Eigen::Matrix3d rr = d.block<3, 3>(3, 3);
    Eigen::Matrix3d rt = d.block<3, 3>(3, 0);
    Eigen::Vector3d axial(rt(2, 1)-rt(1, 2), rt(0, 2)-rt(2, 0), rt(1, 0)-rt(0, 1));
    Eigen::Matrix3d a = rr.trace()*Eigen::Matrix3d::Identity()-rr;
    return a.ldlt().solve(-axial);
}

} // namespace ResistanceMath
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_RESISTANCE_MATH_H_*/
