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
 * difference,
 *
 *     dq = h [N F + sqrt(2 kT/h) N^1/2 W + (kT/delta) (N(q + delta D W'/2) - N(q - delta D W'/2)) D^-1 W'],
 *
 * q each body's position and orientation (moved by a rotation vector in the lab frame, Q <- Q R^T),
 * D = diag(l, l, l, 1, 1, 1) with l a length over which N changes (the smallest blob radius), and
 * the random finite difference taken in the lab frame, where the divergence is. N is each body's
 * own 6x6 mobility (TypeStepCoefficients::mobility) without hydrodynamic interactions (the
 * difference then only turns it with the body), their coupled mobility with them (BodyMobility,
 * dense or matrix-free). The velocities it leaves in the states are the displacements over h.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN BrownianBodyStep {
public:
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
    /** The iterations the last step's matrix-free solves took: Lanczos, then GMRES's three solves summed. */
    HydrodynamicInteractions::KrylovIterations getLastIterations() const {
        return lastIterations;
    }
private:
    typedef Eigen::Matrix<double, 6, 1> Vector6;
    /** Every body's generalised force in its active body-frame coordinates, body after body. */
    Eigen::VectorXd generalizedForces(const std::vector<BodyState>& states, const std::vector<OpenMM::Vec3>& forces) const;
    /** The velocities (active body-frame coordinates) of N F and the noise, without interactions. */
    Eigen::VectorXd ownVelocities(const Eigen::VectorXd& g, const CoupledStepParameters& step, const std::vector<TypeStepCoefficients>& coefficients,
                                  const std::function<double ()>& normal) const;
    /** The same with interactions, dense or matrix-free. */
    Eigen::VectorXd coupledVelocities(const std::vector<BodyState>& states, const Eigen::VectorXd& g, const CoupledStepParameters& step,
                                      const CoupledSolve& solve, const std::function<double ()>& normal, BlobMobility& mobility);
    /** The random finite difference's drift kT (d/dq . N) (lab frame, 6 per body). */
    std::vector<Vector6> drift(const std::vector<BodyState>& states, const CoupledStepParameters& step, const CoupledSolve& solve,
                               const std::vector<TypeStepCoefficients>& coefficients, const std::function<double ()>& normal, BlobMobility& mobility);
    /** N(q) g for lab generalised vectors g (6 per body) at states q, as lab vectors. */
    std::vector<Vector6> labMobility(const std::vector<BodyState>& states, const std::vector<Vector6>& g, const CoupledStepParameters& step,
                                     const CoupledSolve& solve, const std::vector<TypeStepCoefficients>& coefficients, BlobMobility& mobility);
    const RigidBodyModel& model;
    const HydrodynamicInteractions* interactions;
    std::unique_ptr<BodyMobility> bodyMobility;
    std::vector<int> firstCoordinate;
    double driftLength;  ///< l of the random finite difference (nm)
    std::vector<double> driftAngle;  ///< per type: the turn (radians) that moves its farthest blob by l, at most 1
    HydrodynamicInteractions::KrylovIterations lastIterations = {0, 0, 0};
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BROWNIAN_BODY_STEP_H_*/
