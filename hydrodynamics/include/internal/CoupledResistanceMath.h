#ifndef RIGID_LANGEVIN_COUPLED_RESISTANCE_MATH_H_
#define RIGID_LANGEVIN_COUPLED_RESISTANCE_MATH_H_

#include "openmm/Vec3.h"
#include "internal/KrylovSolvers.h"
#include "internal/windowsExportHydrodynamics.h"
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The dense algebra of bodies coupled through the solvent (CoupledResistance), for the classes and
 * kernels that build on it: the integrator's model and the host platforms apply exactly these.
 */
namespace CoupledResistanceMath {

/** The name of body b in messages (such as "rigid body 3"); where none is given, "body b". */
typedef std::function<std::string (int body)> BodyNames;

/**
 * Throw an OpenMMException, beginning with caller, unless the blobs at positions with radii (blob k
 * belonging to body owner[k], the bodies' blobs in order) can be coupled, in the periodic box of
 * boxVectors (three) if given, above the no-slip wall z = wallZ if given: BeadHydrodynamics::
 * validate() (finite positions, positive finite radii, no two blobs the same sphere, on one body
 * or on two); in a box, PeriodicRotnePragerYamakawa::validate() (every blob's diameter under half
 * the box's smallest width; no two blobs the same sphere through the box); above a wall,
 * RotnePragerBlake::validate() (every blob's centre above the wall, which throws a
 * RotnePragerBlake::BlobBelowWallException; no two blobs raised to the same sphere); a box and a
 * wall together are refused. Blobs are named "blob i of " the body's name. The dense and the
 * matrix-free paths both check this before using the blobs.
 */
OPENMM_EXPORT_HYDRODYNAMICS void validateBlobs(const std::string& caller, const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii,
                                               const std::vector<int>& owner, const OpenMM::Vec3* boxVectors, const BodyNames& bodyNames = BodyNames(),
                                               std::optional<double> wallZ = std::nullopt);

/**
 * R = K^T M^-1 K per unit viscosity (lab frame; see CoupledResistance) for blobs at positions with
 * radii, blob k belonging to body owner[k], the bodies' reference points at origins; in a periodic
 * box if boxVectors (three) is given (M then PeriodicRotnePragerYamakawa's, each body's blobs
 * taken where they are, relative to its origin); above a no-slip wall, the plane z = wallZ, if
 * wallZ is given (M then RotnePragerBlake's, regularised). Throws an OpenMMException, beginning
 * with caller, for blobs that validateBlobs() refuses (naming them by bodyNames), or if M cannot be
 * factorised. M is factorised by BeadHydrodynamics::choleskyInPlace (AVX2/FMA where the CPU has
 * it); from 200 blobs all runs on BeadHydrodynamics::getNumThreads() threads: M formed, the
 * factorisation's updates, the triangular solve and R's lower triangle each in parts that do not
 * depend on the number of threads.
 */
OPENMM_EXPORT_HYDRODYNAMICS Eigen::MatrixXd resistance(const std::string& caller, const std::vector<OpenMM::Vec3>& positions,
                                                       const std::vector<double>& radii, const std::vector<int>& owner,
                                                       const std::vector<OpenMM::Vec3>& origins, const OpenMM::Vec3* boxVectors = NULL,
                                                       const BodyNames& bodyNames = BodyNames(), std::optional<double> wallZ = std::nullopt);

/**
 * The lower triangle of a 3n x 3n matrix (the upper is left unset) from its 3x3 blocks:
 * block(i, j, values) writes block (i, j), row-major, for every j <= i; rows shared out by parallel.
 */
template <class Block>
Eigen::MatrixXd lowerTriangle(int n, const Block& block, const KrylovSolvers::ParallelFor& parallel) {
    Eigen::MatrixXd m(3*n, 3*n);
    parallel(n, [&] (int begin, int end) {
        for (int i = begin; i < end; i++)
            for (int j = 0; j <= i; j++) {
                double values[9];
                block(i, j, values);
                for (int k = 0; k < 3; k++)
                    for (int l = 0; l < 3; l++)
                        m(3*i+k, 3*j+l) = values[3*k+l];
            }
    });
    return m;
}

/**
 * The blobs' generalised RPY mobility M per unit viscosity (unbounded solvent), 3N x 3N: its lower
 * triangle (the upper is left unset), rows shared out by parallel.
 */
OPENMM_EXPORT_HYDRODYNAMICS Eigen::MatrixXd mobilityMatrix(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii,
                                                           const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially);

/**
 * out = M f: the blobs' generalised RPY mobility per unit viscosity (unbounded solvent) applied to
 * forces f (3 per blob) without forming M, its rows shared out by parallel.
 */
OPENMM_EXPORT_HYDRODYNAMICS void mobilityProduct(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const Eigen::VectorXd& f,
                                                 Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially);

/**
 * The calibration of a body whose blobs alone have resistance D (blobResistance) but whose own
 * friction is Xi (own), both symmetric positive definite and of the same size: the symmetric
 * positive definite T with T D T = Xi,
 *
 *     T = D^-1/2 (D^1/2 Xi D^1/2)^1/2 D^-1/2   (the identity when D = Xi).
 *
 * Coupled bodies then have the resistance T^T R T (T block-diagonal over the bodies): a congruence,
 * so it stays symmetric positive definite for every configuration; a lone body has exactly Xi; and
 * as the blobs resolve the body (D -> Xi) it becomes R itself. Throws an OpenMMException beginning
 * with caller if D or Xi is not positive definite.
 */
OPENMM_EXPORT_HYDRODYNAMICS Eigen::MatrixXd calibration(const std::string& caller, const Eigen::MatrixXd& blobResistance, const Eigen::MatrixXd& own);

} // namespace CoupledResistanceMath
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_COUPLED_RESISTANCE_MATH_H_*/
