#ifndef RIGID_LANGEVIN_BROWNIAN_BODY_STEP_H_
#define RIGID_LANGEVIN_BROWNIAN_BODY_STEP_H_

#include "internal/BodyMobility.h"
#include "internal/CoupledBodyStep.h"
#include "internal/StepCoefficients.h"
#include "internal/windowsExportRigidLangevin.h"
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * One step of overdamped Brownian dynamics of rigid bodies (RigidBrownianIntegrator), written once
 * for every platform: Euler-Maruyama with the stochastic drift kT (d/dq . N) from a random finite
 * difference along a random direction D w (w six normals per body, lab frame),
 *
 *     dq = h [N F + sqrt(2 kT/h) N^1/2 W + kT (d/d(D w) N) D^-1 w],
 *
 * q each body's position and orientation (moved by a rotation vector in the lab frame, Q <- Q R^T),
 * D = diag(l, l, l, theta, theta, theta) with l a length over which N changes (the smallest blob
 * radius) and theta the turn of the body that moves its farthest blob by l. N is each body's own
 * 6x6 mobility (TypeStepCoefficients::mobility) without hydrodynamic interactions, their coupled
 * mobility with them (BodyMobility, dense or matrix-free). The velocities it leaves in the states
 * are the displacements over h.
 *
 * The derivative along D w is a central difference over +-delta/2 D w. Dense and without
 * interactions, of N itself (exact solves: delta = 1e-4). Matrix-free, of the parts of N = A (K'^T
 * M^-1 K')^-1 A^T (A: body frame to lab) in the traction form of Sprinkle, Balboa Usabiaga, Patankar
 * and Donev (J. Chem. Phys. 147, 244103 (2017)): with U = N A^T D^-1 w and lambda = M^-1 K' U from
 * one solve at q,
 *
 *     (dN) D^-1 w = (dA) U + A N [(dA^T) D^-1 w - (dK'^T) lambda] + A N K'^T M^-1 [(dM) lambda - (dK') U],
 *
 * whose last two terms join the step's own solve as a force and a slip. Its differences are of
 * products, not of solves, so delta need not outgrow the solves' error: one solve fewer a step
 * (one Lanczos and two GMRES solves rather than three) and no error of tolerance/delta.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN BrownianBodyStep {
public:
    typedef Eigen::Matrix<double, 6, 1> Vector6;
    /** interactions: null without hydrodynamic interactions. */
    BrownianBodyStep(const RigidBodyModel& model, const HydrodynamicInteractions* interactions);
    /**
     * Advance every body's state by one step.
     *
     * @param states        every body's state, in place
     * @param forces        the particles' forces (lab frame) at the states' positions
     * @param step          the step size, viscosity, kT and box
     * @param solve         with interactions: dense or matrix-free, and how far
     * @param coefficients  each type's mobility (without interactions)
     * @param normal        standard normal numbers, drawn in a fixed order
     * @param mobility      the blobs' mobility products (matrix-free)
     */
    void take(std::vector<BodyState>& states, const std::vector<OpenMM::Vec3>& forces, const CoupledStepParameters& step, const CoupledSolve& solve,
              const std::vector<TypeStepCoefficients>& coefficients, const std::function<double ()>& normal, BlobMobility& mobility);
    /**
     * The drift velocity kT (d/d(D w) N) D^-1 w of the random direction w (6 per body, lab frame) as
     * the step takes it (its mean over w is kT d/dq . N): lab velocities, 6 per body.
     */
    std::vector<Vector6> drift(const std::vector<BodyState>& states, const std::vector<Vector6>& w, const CoupledStepParameters& step,
                               const CoupledSolve& solve, const std::vector<TypeStepCoefficients>& coefficients, BlobMobility& mobility);
    /** The iterations the last step's matrix-free solves took: Lanczos, then GMRES's drift solve, then its step solve. */
    HydrodynamicInteractions::KrylovIterations getLastIterations() const {
        return lastIterations;
    }
private:
    /** The matrix-free drift of w as a generalised force and a slip for the step's solve (their
     *  response A N (force + K'^T M^-1 slip)/viscosity), and lab velocities besides (6 per body). */
    struct DriftTerms {
        Eigen::VectorXd force, slip;
        std::vector<Vector6> velocity;
    };
    /** Every body's generalised force in its active body-frame coordinates, body after body. */
    Eigen::VectorXd generalizedForces(const std::vector<BodyState>& states, const std::vector<OpenMM::Vec3>& forces) const;
    /** The velocities (active body-frame coordinates) of N F and the noise, without interactions. */
    Eigen::VectorXd ownVelocities(const Eigen::VectorXd& g, const CoupledStepParameters& step, const std::vector<TypeStepCoefficients>& coefficients,
                                  const std::function<double ()>& normal) const;
    /** The same with interactions, dense. */
    Eigen::VectorXd denseVelocities(const std::vector<BodyState>& states, const Eigen::VectorXd& g, const CoupledStepParameters& step,
                                    const std::function<double ()>& normal);
    /** The same matrix-free, the drift's force and slip (tractionTerms) in its solve; the drift's lab velocity outside the solve in driftVelocity. */
    Eigen::VectorXd krylovVelocities(const std::vector<BodyState>& states, Eigen::VectorXd g, const CoupledStepParameters& step,
                                     const CoupledSolve& solve, const std::function<double ()>& normal, BlobMobility& mobility,
                                     std::vector<Vector6>& driftVelocity);
    /** Every body's lab 6-vector in its active body-frame coordinates, body after body, and back. */
    Eigen::VectorXd toActive(const std::vector<BodyState>& states, const std::vector<Vector6>& lab) const;
    std::vector<Vector6> toLab(const std::vector<BodyState>& states, const Eigen::VectorXd& active) const;
    /** Six normals per body. */
    std::vector<Vector6> randomDirections(const std::function<double ()>& normal) const;
    /** D^-1 w: the lab generalised forces whose mobility the difference takes. */
    std::vector<Vector6> directionForces(const std::vector<Vector6>& w) const;
    /** The states moved by sign (delta/2) D w. */
    std::vector<BodyState> displaced(const std::vector<BodyState>& states, const std::vector<Vector6>& w, double sign, double delta) const;
    /** The drift as a central difference of N (dense, or each body's own). */
    std::vector<Vector6> mobilityDifference(const std::vector<BodyState>& states, const std::vector<Vector6>& w, const CoupledStepParameters& step,
                                            const std::vector<TypeStepCoefficients>& coefficients);
    /** The matrix-free drift's terms (one solve at the states, then two products with M and K', K'^T, A at the displaced ones). */
    DriftTerms tractionTerms(const std::vector<BodyState>& states, const std::vector<Vector6>& w, const CoupledStepParameters& step,
                             const CoupledSolve& solve, BlobMobility& mobility);
    /** N(q) g for lab generalised vectors g (6 per body) at states q, as lab vectors (dense, or each body's own). */
    std::vector<Vector6> labMobility(const std::vector<BodyState>& states, const std::vector<Vector6>& g, const CoupledStepParameters& step,
                                     const std::vector<TypeStepCoefficients>& coefficients);
    const RigidBodyModel& model;
    const HydrodynamicInteractions* interactions;
    std::unique_ptr<BodyMobility> bodyMobility;
    std::vector<int> firstCoordinate;
    int numCoordinates;  ///< every body's active coordinates together
    double driftLength;  ///< l of the random finite difference (nm)
    std::vector<double> driftAngle;  ///< per type: the turn (radians) that moves its farthest blob by l, at most 1
    HydrodynamicInteractions::KrylovIterations lastIterations = {0, 0, 0};
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BROWNIAN_BODY_STEP_H_*/
