#ifndef RIGID_LANGEVIN_COUPLED_BODY_STEP_H_
#define RIGID_LANGEVIN_COUPLED_BODY_STEP_H_

#include "internal/BlobMobility.h"
#include "internal/HydrodynamicInteractions.h"
#include "internal/KrylovSolvers.h"
#include "internal/RigidBodyModel.h"
#include "internal/windowsExportRigidLangevin.h"
#include "openmm/Vec3.h"
#include <functional>
#include <vector>

namespace RigidLangevinPlugin {

/** How the coupled friction step solves: the integrator's hydrodynamic settings, resolved for a platform and a size. */
struct CoupledSolve {
    bool krylov;         ///< matrix-free (HydrodynamicInteractions::krylovFrictionStep) rather than dense
    double tolerance;    ///< the matrix-free solves' relative tolerance
    int maxIterations;   ///< each matrix-free solve's iteration limit (it throws beyond)
    bool spectral;       ///< matrix-free in a periodic box with the positively split Ewald products (SpectralBlobMobility)
};

/** The parameters of one step. */
struct CoupledStepParameters {
    double stepSize, viscosity, kT;
    const OpenMM::Vec3* box;   ///< the periodic box's three vectors, or NULL
};

/**
 * The step of bodies coupled through the solvent, written once for every platform: BAOAB with
 * the midpoint friction step of all bodies at once (HydrodynamicInteractions). For every body:
 * its rotation made orthonormal again (a platform in single precision stores it rounded), the
 * force's full kick (the two half kicks of consecutive steps are one) and half a drift; then the
 * friction and noise of all bodies together, dense or matrix-free; then every body's second half
 * drift. A platform supplies the states and the particles' forces, its normal numbers, where the
 * blobs' mobility products are computed and the threads for the per-body work.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN CoupledBodyStep {
public:
    CoupledBodyStep(const RigidBodyModel& model, const HydrodynamicInteractions& interactions);
    /**
     * Advance every body's state by one step.
     *
     * @param states    every body's state (the model's bodies, free particles included), in place
     * @param forces    the particles' forces (lab frame) at the states' positions
     * @param step      the step size, viscosity, kT and box
     * @param solve     dense or matrix-free, and how far
     * @param normal    standard normal numbers: one per coordinate when dense; three per blob when
     *                  matrix-free, none at kT = 0
     * @param mobility  the blobs' mobility products (matrix-free)
     * @param parallel  runs the per-body work over ranges of bodies
     */
    void take(std::vector<BodyState>& states, const std::vector<OpenMM::Vec3>& forces, const CoupledStepParameters& step, const CoupledSolve& solve,
              const std::function<double ()>& normal, BlobMobility& mobility, const KrylovSolvers::ParallelFor& parallel);
    /** The iterations the last step's matrix-free solves took (all zero after a dense one). */
    HydrodynamicInteractions::KrylovIterations getLastIterations() const {
        return lastIterations;
    }
private:
    /** The friction and noise of all bodies together, after the first half drift. */
    void frictionStep(std::vector<BodyState>& states, const CoupledStepParameters& step, const CoupledSolve& solve,
                      const std::function<double ()>& normal, BlobMobility& mobility);
    const RigidBodyModel& model;
    const HydrodynamicInteractions& interactions;
    HydrodynamicInteractions::KrylovIterations lastIterations = {0, 0, 0};
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_COUPLED_BODY_STEP_H_*/
