#ifndef RIGID_LANGEVIN_BODY_MOBILITY_H_
#define RIGID_LANGEVIN_BODY_MOBILITY_H_

#include "internal/BlobMobility.h"
#include "internal/HydrodynamicInteractions.h"
#include "internal/KrylovSolvers.h"
#include "internal/RigidBodyModel.h"
#include "internal/windowsExportRigidLangevin.h"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The mobility of bodies coupled through the solvent, N = R^-1 with R = K'^T M^-1 K' their
 * (calibrated) rigid-multiblob resistance per unit viscosity (HydrodynamicInteractions), as
 * overdamped dynamics needs it: N g for generalised forces g, together with the noise N K'^T
 * M^-1 s of a slip s on the blobs (with s = M^1/2 w its covariance is N). Coordinates are the
 * bodies' active generalised coordinates, each body in its own frame (HydrodynamicInteractions).
 *
 * Dense: R formed and factorised (Cholesky), the noise N^1/2 w' as L^-T w' (R = L L^T), exact.
 * Matrix-free: the saddle-point problem of the rigid multiblob method (Usabiaga et al., CAMCOS 11,
 * 217 (2016)),
 *
 *     [ M    -K' ] [ lambda ]   [ -s ]
 *     [ -K'^T  0 ] [   U    ] = [ -g ],    U = N (g + K'^T M^-1 s),
 *
 * solved by GMRES preconditioned by every body's own blocks (its blobs' M_bb and K'_b, exact per
 * body, factorised once per type), the slip s = M^1/2 w by Lanczos; every product with M is the
 * platform's (BlobMobility). A solve that fails throws, naming it, why and what to do.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN BodyMobility {
public:
    explicit BodyMobility(const HydrodynamicInteractions& interactions);
    /** The dense path: factorise the bodies' resistance at these states (box: periodic, or NULL). */
    void factorize(const std::vector<BodyState>& states, const OpenMM::Vec3* box);
    /** Dense: out = N g (after factorize()). */
    void denseMultiply(const Eigen::VectorXd& g, Eigen::VectorXd& out) const;
    /** Dense: out = N^1/2-like noise L^-T w (covariance N), one normal per coordinate in w. */
    void denseNoise(const Eigen::VectorXd& w, Eigen::VectorXd& out) const;
    /**
     * Matrix-free: out = N (g + K'^T M^-1 slip) for the bodies in these states (an empty slip is
     * zero), the mobility products by mobility. Returns the GMRES iterations. blobForces, if given,
     * receives the blobs' lab forces lambda = M^-1 (K' out - slip), which balance g (K'^T lambda = g).
     */
    int solve(const std::vector<BodyState>& states, const Eigen::VectorXd& g, const Eigen::VectorXd& slip, Eigen::VectorXd& out,
              double tolerance, int maxIterations, BlobMobility& mobility, const OpenMM::Vec3* box, Eigen::VectorXd* blobForces = NULL);
    /** out = M f at these states: the blobs' lab velocities under lab forces f (3 per blob). */
    void blobVelocities(const std::vector<BodyState>& states, const Eigen::VectorXd& f, Eigen::VectorXd& out, BlobMobility& mobility,
                        const OpenMM::Vec3* box);
    /** K' u (the blobs' lab velocities of generalised velocities u) and K'^T f (the generalised forces of lab blob forces f), at these states. */
    void applyK(const std::vector<BodyState>& states, const Eigen::VectorXd& u, Eigen::VectorXd& out) const;
    void applyKT(const std::vector<BodyState>& states, const Eigen::VectorXd& f, Eigen::VectorXd& out) const;
    /**
     * Matrix-free: slip of covariance M at these states, from normals drawn from normal(): the
     * product's own noise where it has one (BlobMobility::hasOwnNoise(): the positively split
     * Ewald sum's, exact through its split, a Lanczos on its sparse real-space part only), else
     * M^1/2 w by Lanczos preconditioned by every body's own blocks, w three normals per blob.
     * Returns the Lanczos iterations.
     */
    int blobNoise(const std::vector<BodyState>& states, const std::function<double ()>& normal, Eigen::VectorXd& slip, double tolerance,
                  int maxIterations, BlobMobility& mobility, const OpenMM::Vec3* box);
private:
    /** Set mobility's blobs from states (checked first), and the blob offsets of every body. */
    void placeBlobs(const std::vector<BodyState>& states, BlobMobility& mobility, const OpenMM::Vec3* box);
    /** The scale of every unknown of the saddle-point problem (see solve()), and mu0, a blob's mobility at the smallest radius. */
    Eigen::VectorXd unitScales(double& mu0) const;
    /** The saddle-point operator and its block preconditioner for the bodies in states. */
    void saddleProduct(const std::vector<BodyState>& states, BlobMobility& mobility, const Eigen::VectorXd& in, Eigen::VectorXd& out) const;
    void blockPreconditioner(const std::vector<BodyState>& states, const Eigen::VectorXd& in, Eigen::VectorXd& out) const;
    const HydrodynamicInteractions& interactions;
    const RigidBodyModel& model;
    std::vector<int> firstBlob;
    int numBlobs;
    /** Per type: its own resistance from its blobs alone, K'^T M_bb^-1 K', factorised (the preconditioner's). */
    std::vector<Eigen::LLT<Eigen::MatrixXd> > ownResistance;
    Eigen::LLT<Eigen::MatrixXd> dense;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BODY_MOBILITY_H_*/
