#ifndef RIGID_LANGEVIN_HYDRODYNAMIC_INTERACTIONS_H_
#define RIGID_LANGEVIN_HYDRODYNAMIC_INTERACTIONS_H_

#include "internal/RigidBodyModel.h"
#include "internal/windowsExportRigidLangevin.h"
#include <Eigen/Core>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * Bodies that feel each other through the solvent, as the integrator moves them: every body's
 * hydrodynamic blobs in its frame (RigidBodyModel::getTypeBlobs) and its calibration, precomputed
 * once per body type, and the coupled resistance of all bodies at given states.
 *
 * Coordinates are the bodies' active generalised coordinates (RigidBodyModel.h, activeCoordinate),
 * body after body: its velocity and angular velocity in its own frame about its centre of mass.
 * The resistance per unit viscosity is T^T (G K^T M^-1 K G^T) T over all blobs (CoupledResistance):
 * G turns each body's rows into its frame, and T, block-diagonal, is each type's calibration
 * (CoupledResistanceMath::calibration) from its blobs' resistance alone to its own friction
 * (BodyType::resistance), so that a body far from every other has exactly its own friction, the
 * one it has without interactions, whatever its blobs.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN HydrodynamicInteractions {
public:
    /** Precompute every type's blobs and calibration; throws an OpenMMException naming a body whose blobs do not resist every motion it makes. */
    explicit HydrodynamicInteractions(const RigidBodyModel& model);
    /** The number of coordinates of all bodies together. */
    int getNumCoordinates() const {
        return masses.size();
    }
    /** The mass or principal moment of inertia of every coordinate. */
    const Eigen::VectorXd& getMasses() const {
        return masses;
    }
    /** The number of blobs of all bodies together. */
    int getNumBlobs() const;
    /** The coupled resistance per unit viscosity of the bodies at these states (see the class
     *  description), in the periodic box of boxVectors (three) if given. */
    Eigen::MatrixXd computeResistance(const std::vector<BodyState>& states, const OpenMM::Vec3* boxVectors = NULL) const;
    /** The generalised velocities of the bodies in these states. */
    Eigen::VectorXd getVelocities(const std::vector<BodyState>& states) const;
    /** Set the velocities and angular momenta of the states from generalised velocities. */
    void setVelocities(const Eigen::VectorXd& u, std::vector<BodyState>& states) const;
private:
    struct TypeBlobs {
        std::vector<OpenMM::Vec3> coords;
        std::vector<double> radii;
        Matrix6 calibration;  // body frame, zero outside the type's active coordinates
    };
    const RigidBodyModel& model;
    std::vector<TypeBlobs> types;
    std::vector<int> firstCoordinate;
    Eigen::VectorXd masses;
};

/**
 * The friction step of bodies coupled through the solvent: the midpoint (Crank-Nicolson) rule for
 * the Ornstein-Uhlenbeck equation M du = -viscosity R u dt + sqrt(2 kT viscosity) R^1/2 dW over h,
 *
 *     u <- (M + h viscosity R/2)^-1 [(M - h viscosity R/2) u + sqrt(2 kT h viscosity) L normals],   L L^T = R,
 *
 * M = diag(masses). It keeps the Maxwell distribution (covariance kT M^-1) exactly for any R and
 * any h, and inside BAOAB it gives a free body's long-time diffusion kT (viscosity R)^-1 exactly
 * at any h, stiff friction included. normals holds R.rows() standard normal numbers (ignored at
 * kT = 0). Throws an OpenMMException if R is not positive definite.
 */
OPENMM_EXPORT_RIGIDLANGEVIN void midpointFrictionStep(const Eigen::MatrixXd& resistance, const Eigen::VectorXd& masses, double viscosity, double kT,
                                                      double h, const Eigen::VectorXd& normals, Eigen::VectorXd& u);

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_HYDRODYNAMIC_INTERACTIONS_H_*/
