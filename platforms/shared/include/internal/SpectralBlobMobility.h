#ifndef RIGID_LANGEVIN_SPECTRAL_BLOB_MOBILITY_H_
#define RIGID_LANGEVIN_SPECTRAL_BLOB_MOBILITY_H_

#include "internal/BlobMobility.h"
#include "internal/KrylovSolvers.h"
#include "internal/PositivelySplitEwald.h"
#include "internal/windowsExportRigidLangevin.h"
#include <memory>
#include <string>

namespace RigidLangevinPlugin {

/**
 * The blobs' mobility products of the integrators' SpectralSolver in a periodic box: the positively
 * split Ewald sum (PositivelySplitEwald: matrix-free, linear cost and memory), on the host, on the
 * threads the platform gives (the kernel base's createSpectralMobility(); OpenCL and CUDA derive
 * CommonPseMobility from this class, which runs the products on the device). Its tolerance epsilon is the integrator's hydrodynamic tolerance: the product's
 * error, at most 0.3 epsilon of |M f| (TestPositivelySplitEwald), then stays below the relative
 * residual at which the Krylov solves stop, and the solves converge on the PSE operator (linear,
 * symmetric, positive definite) as on the dense one. A tolerance below
 * PositivelySplitEwald::MinTolerance, which the PSE cannot reach, is refused naming the setting.
 * What PositivelySplitEwald::setBlobs refuses (PseRefusal: the memory budget, the integrator's
 * setHydrodynamicMemoryBudget(), checked before anything large is allocated; more distinct radii
 * than it takes; a box too narrow for the blobs) is rethrown naming the integrator's settings that
 * would change it, and only those.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN SpectralBlobMobility : public BlobMobility {
public:
    /**
     * @param integratorName  the integrator's class name, for messages
     * @param parallel        the platform's threads
     */
    SpectralBlobMobility(const std::string& integratorName, const KrylovSolvers::ParallelFor& parallel);
    /** The PSE's epsilon from now on: the integrator's hydrodynamic tolerance (throws if the PSE cannot reach it). */
    void setTolerance(double tolerance) override;
    /** The most bytes the PSE may hold from the next setBlobs() on: the integrator's hydrodynamic memory budget. */
    void setMemoryBudget(double bytes);
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors = NULL) override;
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) override;
    /** The PSE's noise, exact through its split (PositivelySplitEwald::sampleNoise()), on the host. */
    bool hasOwnNoise() const override {
        return true;
    }
    KrylovSolvers::Result sampleNoise(const std::function<double()>& normal, Eigen::VectorXd& out, double tolerance, int maxIterations) override;
    /** The PSE in use (after setTolerance()), e.g. for its grid and memory. */
    const PositivelySplitEwald& getProduct() const;
private:
    std::string integratorName;
    KrylovSolvers::ParallelFor parallel;
    double memoryBudget;
    std::unique_ptr<PositivelySplitEwald> product;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_SPECTRAL_BLOB_MOBILITY_H_*/
