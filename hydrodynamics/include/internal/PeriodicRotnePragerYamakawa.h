#ifndef RIGID_LANGEVIN_PERIODIC_ROTNE_PRAGER_YAMAKAWA_H_
#define RIGID_LANGEVIN_PERIODIC_ROTNE_PRAGER_YAMAKAWA_H_

#include "openmm/Vec3.h"
#include "internal/KrylovSolvers.h"
#include "internal/windowsExportHydrodynamics.h"
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The blobs' generalised Rotne-Prager-Yamakawa mobility in a periodic box (any triclinic box),
 * per unit viscosity, by an Ewald sum whose two parts are each positive semidefinite.
 *
 * The generalised RPY tensor (overlapping and unequal blobs included) is the Oseen tensor averaged
 * over both blobs' surfaces; in Fourier space it is sinc(k a_i) sinc(k a_j) (I - kk)/k^2. The
 * periodic mobility sums that over the reciprocal lattice without k = 0 (the fluid at rest on
 * average; Hasimoto 1959). Hasimoto's split (as in the positively split Ewald method, Fiore et al.,
 * J. Chem. Phys. 146, 124116 (2017)) divides it with phi(k) = (1 + k^2/4xi^2) exp(-k^2/4xi^2),
 * between 0 and 1, into
 *
 *   a wave-space part   (1/V) sum_{k != 0} phi(k) sinc(k a_i) sinc(k a_j) (I - kk)/k^2 cos(k.r)
 *   a real-space part   sum_n F(r + n),  F = RPY(r) - G(r),
 *
 * G being the inverse Fourier transform over all k of phi times the tensor: F is positive (the
 * weight 1 - phi is), short-ranged (phi = 1 - O(k^4), so no dipolar tail survives), and G(r) is
 * evaluated in closed form (HasimotoSplit.h).
 * Both sums are cut where their terms fall below 1e-16 of the leading ones; xi only moves work
 * between them (the tests check the result does not depend on it). Exact for every configuration,
 * overlapping blobs and blobs overlapping their own images included; a lone blob in a cube of side
 * L, apart from its images (2a < L), has the mobility (1 - 2.837297 a/L + 4 pi/3 (a/L)^3)/(6 pi a)
 * exactly. Bodies made of blobs need blobs under half the box across (validate()).
 *
 * Dense, O(N^2) times the number of wave vectors and images: the definition of correct that faster
 * periodic methods (PositivelySplitEwald) are tested against. The pairs and the wave vectors are
 * shared out by the caller's ParallelFor.
 */
class OPENMM_EXPORT_HYDRODYNAMICS PeriodicRotnePragerYamakawa {
public:
    /**
     * @param boxVectors  the box's three vectors (nm), in OpenMM's reduced form
     * @param splitting   Hasimoto's xi (1/nm); 0 chooses one that balances the two sums
     */
    PeriodicRotnePragerYamakawa(const OpenMM::Vec3 boxVectors[3], double splitting = 0);
    typedef KrylovSolvers::ParallelFor ParallelFor;
    /** The 3N x 3N mobility of blobs at positions with radii (both halves filled). */
    Eigen::MatrixXd mobility(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii,
                             const ParallelFor& parallel = KrylovSolvers::sequentially) const;
    double getSplitting() const {
        return xi;
    }
    /** The real-space pair function F (3x3, row-major) of blobs with radii ai, aj, j at offset d from i. */
    void realSpaceBlock(const OpenMM::Vec3& d, double ai, double aj, double block[9]) const;
    /** The box's smallest width (nm): the least distance between two opposite faces, which no
     *  two images of a point are closer than. */
    double getSmallestWidth() const;
    /**
     * Throw an OpenMMException, beginning with caller and naming blobs by names, unless blobs
     * (finite, with positive radii: BeadHydrodynamics::validate()) suit the box:
     *  - every blob's diameter is under half the box's smallest width. Then no two blobs, nor a
     *    blob and its own images, overlap more than one image of each other: the near field of
     *    every pair is that of its nearest images, as a body's particles must be within half the
     *    box to be one body. Larger blobs overlap several images at once, where the
     *    overlap-regularised RPY kernel no longer describes spheres in a box (nor Hasimoto's
     *    a/L expansion a sphere among its images), though the sum itself stays defined;
     *  - no two blobs are the same sphere through the box (positions a box vector apart, to 1e-10
     *    of the radius, equal radii): M would be singular.
     */
    void validate(const std::string& caller, const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii,
                  const std::function<std::string (int blob)>& names) const;
private:
    /** d less the lattice vector that puts it into the box's reduced cell. */
    OpenMM::Vec3 reduced(OpenMM::Vec3 d) const;
    void addRealSpace(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, Eigen::MatrixXd& m, const ParallelFor& parallel) const;
    void addWaveSpace(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, Eigen::MatrixXd& m, const ParallelFor& parallel) const;
    /** Half the reciprocal lattice (one of k and -k) within the wave cutoff, k = 0 left out. */
    std::vector<OpenMM::Vec3> waveVectors() const;
    OpenMM::Vec3 box[3], reciprocal[3];
    double volume, xi, realCutoffBeyondContact, waveCutoff;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PERIODIC_ROTNE_PRAGER_YAMAKAWA_H_*/
