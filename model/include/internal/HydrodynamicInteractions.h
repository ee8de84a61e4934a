#ifndef RIGID_LANGEVIN_HYDRODYNAMIC_INTERACTIONS_H_
#define RIGID_LANGEVIN_HYDRODYNAMIC_INTERACTIONS_H_

#include "internal/BlobMobility.h"
#include "internal/KrylovSolvers.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/RigidBodyModel.h"
#include <Eigen/Cholesky>
#include "internal/windowsExportRigidLangevin.h"
#include <Eigen/Core>
#include <optional>
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
    /**
     * Precompute every type's blobs and calibration; throws an OpenMMException naming a body whose
     * blobs do not resist every motion it makes. wallZ: the height of a no-slip wall bounding the
     * fluid (the blobs' mobility then Rotne-Prager-Blake's), or none.
     */
    explicit HydrodynamicInteractions(const RigidBodyModel& model, std::optional<double> wallZ = std::nullopt);
    /** The no-slip wall's height, or none. */
    std::optional<double> getWall() const {
        return wallZ;
    }
    /** The model whose bodies these are. */
    const RigidBodyModel& getModel() const {
        return model;
    }
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
    /** The smallest blob radius of any body type (nm): the length over which the blobs' mobility changes. */
    double getSmallestBlobRadius() const;
    /** How many distinct blob radii the body types have (the positively split Ewald sum takes a few). */
    int getNumBlobRadii() const;
    /** The coupled resistance per unit viscosity of the bodies at these states (see the class
     *  description), in the periodic box of boxVectors (three) if given. */
    Eigen::MatrixXd computeResistance(const std::vector<BodyState>& states, const OpenMM::Vec3* boxVectors = NULL) const;
    /** The generalised velocities of the bodies in these states. */
    Eigen::VectorXd getVelocities(const std::vector<BodyState>& states) const;
    /** Set the velocities and angular momenta of the states from generalised velocities. */
    void setVelocities(const Eigen::VectorXd& u, std::vector<BodyState>& states) const;
    /** The iterations each Krylov method took in krylovFrictionStep() (0 for the noise's at zero temperature). */
    struct KrylovIterations {
        int noise, noiseSolve, friction;
    };
    /**
     * The midpoint friction step of midpointFrictionStep() for the bodies in these states, in the
     * periodic box of boxVectors (three) if given, matrix-free: R is never formed. With K' the bodies' (calibrated) blob velocities
     * from u, M the blobs' mobility, M_b the bodies' masses and c = h viscosity/2,
     *
     *   noise    xi = sqrt(2 kT h viscosity) K'^T M^-1 M^1/2 W   (covariance 2 kT h viscosity R: Lanczos, then
     *                                                            conjugate gradients on M)
     *   friction (M_b + c R)^-1 z = M_b^-1 (z - K'^T y),  (M/c + K' M_b^-1 K'^T) y = K' M_b^-1 z
     *                                                           (Woodbury; conjugate gradients)
     *
     * with z = 2 M_b u + xi, u' = (M_b + c R)^-1 z - u. Each solve is preconditioned by every body's
     * own blocks (fixed in its frame, so factorised once per body type) and stopped at relative
     * residual tolerance. The blobs are checked first as the dense path checks them
     * (CoupledResistanceMath::validateBlobs: finite, no two the same sphere, in a box not too
     * large for it), naming the body and blob; a solve that does not converge in maxIterations,
     * finds its operator not positive definite or meets a product that is not finite throws, naming
     * which solve (the Lanczos square root or the conjugate gradients for the noise, or those for
     * the friction), why (KrylovSolvers::explain) and what to do. normals: 3 per blob. The
     * products of M are mobility's (given the blobs here: on the host, HostBlobMobility; on a
     * device, the platform's own).
     */
    KrylovIterations krylovFrictionStep(const std::vector<BodyState>& states, double viscosity, double kT, double h, const Eigen::VectorXd& normals,
                                        Eigen::VectorXd& u, double tolerance, int maxIterations, BlobMobility& mobility,
                                        const OpenMM::Vec3* boxVectors = NULL) const;
    /**
     * krylovFrictionStep()'s friction solve starts from the best multiple of the last one's solution
     * (KrylovSolvers::scaledStart: fewer iterations, the same step to the tolerance). That solution is
     * no part of a checkpoint: forget it (start the next solve from zero) wherever a run must repeat
     * exactly from the states alone: when a checkpoint is written or loaded, and when states are set.
     */
    void forgetWarmStart() const;
    /** Warm starts on (the default) or off, e.g. to measure what they save; forgets the last solution. */
    void setWarmStarts(bool warm);
    /** The blobs' lab positions and radii, all bodies in order. */
    void placeBlobs(const std::vector<BodyState>& states, std::vector<OpenMM::Vec3>& positions, std::vector<double>& radii) const;
    /** The first of a body's coordinates (its active generalised coordinates follow, getNumDegreesOfFreedom() of them). */
    int getFirstCoordinate(int body) const {
        return firstCoordinate[body];
    }
    /** K' of a body type in its frame: the body-frame velocities of its blobs (3 per blob) from its active generalised velocities (calibrated). */
    const Eigen::MatrixXd& getTypeBlobVelocities(int type) const {
        return types[type].velocities;
    }
    /** The mobility of a body type's own blobs in its frame (3 per blob), factorised. */
    const Eigen::LLT<Eigen::MatrixXd>& getTypeSelfMobility(int type) const {
        return types[type].selfMobility;
    }
    /** Which operation of every body's own mobility factor applySelfFactor() applies. */
    enum SelfFactor {
        Lower,                  // L v
        InverseLower,           // L^-1 v
        InverseLowerTranspose   // L^-T v
    };
    /**
     * out = the block-diagonal L (or its inverse, or inverse transpose) of blob vectors (3 per blob,
     * lab frame, all bodies in order), L L^T the bodies' own blocks of the blobs' mobility at these
     * states: each body's block is Q L_t, its type's Cholesky factor in its frame turned to the lab.
     * The Krylov noise is taken through it, preconditioned (KrylovSolvers::lanczosPower).
     */
    void applySelfFactor(const std::vector<BodyState>& states, SelfFactor which, const Eigen::VectorXd& in, Eigen::VectorXd& out) const;
    /**
     * The operator L^-1 M L^-T (M the blobs' mobility by mobility's products, L applySelfFactor()'s),
     * whose Lanczos iterations give the noise of either step; states and mobility must outlive it.
     */
    KrylovSolvers::Operator preconditionedMobility(const std::vector<BodyState>& states, BlobMobility& mobility) const;
    /** Throw, naming body and blob, where blobs placed from states cannot be solved (HydrodynamicInteractions' checks, shared by every path). */
    void validateBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors) const;
private:
    struct TypeBlobs {
        std::vector<OpenMM::Vec3> coords;
        std::vector<double> radii;
        Matrix6 calibration;  // body frame, zero outside the type's active coordinates
        Eigen::MatrixXd velocities;                     // body-frame blob velocities from the active generalised velocities: K' in the body frame
        Eigen::LLT<Eigen::MatrixXd> selfMobility;       // the blobs' own M block (body frame), factorised
        mutable double frictionScale;                   // the c of friction below
        mutable Eigen::LLT<Eigen::MatrixXd> friction;   // M/c + K' M_b^-1 K'^T for this body alone (body frame), factorised
    };
    /** The bodies' names for messages about their blobs (RigidBodyModel::getBodyName). */
    CoupledResistanceMath::BodyNames bodyNames() const;
    const RigidBodyModel& model;
    std::optional<double> wallZ;
    std::vector<TypeBlobs> types;
    std::vector<int> firstCoordinate;
    Eigen::VectorXd masses;
    bool warmStarts = true;
    mutable Eigen::VectorXd lastFrictionSolution;  // the last friction solve's y (lab frame), empty when forgotten
};

/** A body's blob vector (3 per blob) from the lab frame into its frame (toBody), or back. */
OPENMM_EXPORT_RIGIDLANGEVIN Eigen::VectorXd turnBlobs(const Eigen::VectorXd& v, const double q[3][3], bool toBody);

/** How an integrator's messages about the coupled bodies begin ("<integrator>: hydrodynamic interactions"). */
OPENMM_EXPORT_RIGIDLANGEVIN std::string hydrodynamicsCaller(const std::string& integrator);

/**
 * The iterations a Krylov solve of the coupled bodies took if it converged; otherwise throw an
 * OpenMMException naming the integrator, the solve, why it failed (KrylovSolvers::explain) and what to do.
 */
OPENMM_EXPORT_RIGIDLANGEVIN int checkHydrodynamicSolve(const std::string& solve, const KrylovSolvers::Result& result, int numBodies, int numBlobs,
                                                       const std::string& integrator);

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
