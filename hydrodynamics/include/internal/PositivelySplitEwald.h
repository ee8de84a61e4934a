#ifndef RIGID_LANGEVIN_POSITIVELY_SPLIT_EWALD_H_
#define RIGID_LANGEVIN_POSITIVELY_SPLIT_EWALD_H_

#include "internal/BlobMobility.h"
#include "internal/KrylovSolvers.h"
#include "internal/windowsExportHydrodynamics.h"
#include <functional>
#include <memory>

namespace RigidLangevinPlugin {

class PseRealSpace;
class PseWaveSpace;
struct PseParameters;

/**
 * The blobs' generalised Rotne-Prager-Yamakawa mobility M in a periodic box (any triclinic box in
 * OpenMM's reduced form), per unit viscosity, as a matrix-free product at linear cost: the
 * positively split Ewald method (PSE; Fiore, Balboa Usabiaga, Donev & Swan, J. Chem. Phys. 146,
 * 124116 (2017)). Hasimoto's split (HasimotoSplit.h, as PeriodicRotnePragerYamakawa) gives
 * M = M_real + M_wave, both positive semidefinite:
 *
 *  - M_real: the pairs within a_i + a_j + sqrt(-ln epsilon)/xi of each other (found with a cell
 *    list, stored once per setBlobs()), F = RPY - G exactly at every distance, overlapping and
 *    unequal blobs included;
 *  - M_wave: Gaussian spreading to a grid, FFT (pocketfft), multiplication by Hasimoto's weight
 *    mode by mode, FFT back, interpolation (spectral Ewald; PseWaveSpace).
 *
 * The tolerance epsilon chooses the real-space cutoff, the grid (Nyquist wave number 1.25 k_c,
 * k_c = 2 xi sqrt(-ln(epsilon/10))), the Gaussian's support P and width (its truncation and the
 * grid's aliasing of it each at most epsilon/100; PseParameters.cpp); the splitting xi moves work
 * between the two parts without changing the answer, and when not given is the one a cost model
 * estimates cheapest. The product M f agrees with the dense Ewald sum PeriodicRotnePragerYamakawa
 * to a relative error |dM f|/|M f| below epsilon (measured: at most 0.3 epsilon for epsilon from
 * 1e-3 to 1e-9, TestPositivelySplitEwald). Memory O(B) plus the grid, the real-space pairs stored
 * in single precision (summed in double) from epsilon = 1e-4 up; setBlobs() checks the total
 * against a budget before anything large is allocated.
 *
 * The noise: sampleNoise() returns a vector of covariance M exactly through the split, M_wave^1/2
 * applied in Fourier space to complex white noise on the grid and M_real^1/2 by Lanczos on the
 * sparse real-space operator.
 *
 * The real-space pairs are taken at their nearest image only, so the real-space cutoff must stay
 * below half the box's narrowest width; blobs of up to MaxRadii distinct radii (each costs two FFTs
 * per product). Threads: every stage (pair search and products, spreading, the FFTs' batches,
 * interpolation) is shared out by the ParallelFor given, with results independent of it.
 */
class OPENMM_EXPORT_HYDRODYNAMICS PositivelySplitEwald : public BlobMobility {
public:
    /** The most distinct blob radii supported. */
    static const int MaxRadii = 4;
    /** The tightest tolerance: at 1e-12 the measured error reached epsilon (rounding in the
     *  closed forms, which cancel to about 1e-13 of a blob's self-mobility, and in the FFTs). */
    static constexpr double MinTolerance = 1e-10;
    /** The loosest tolerance accepted. */
    static constexpr double MaxTolerance = 0.1;
    /** The memory budget unless set: 4 GiB. */
    static constexpr double DefaultMemoryBudget = 4.0*1024*1024*1024;
    /**
     * @param tolerance  epsilon, the relative error of M f, in [MinTolerance, MaxTolerance]
     * @param splitting  Hasimoto's xi (1/nm); 0 chooses the one estimated cheapest at each setBlobs()
     * @param parallel   shares out the work (KrylovSolvers::ParallelFor)
     */
    explicit PositivelySplitEwald(double tolerance = 1e-3, double splitting = 0, const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially);
    ~PositivelySplitEwald();
    /** The most bytes setBlobs() may hold (grid, spectra, real-space pairs, per-blob data). */
    void setMemoryBudget(double bytes);
    double getMemoryBudget() const {
        return memoryBudget;
    }
    /**
     * The blobs for the products that follow. boxVectors (three, OpenMM's reduced form) is required.
     * Throws an OpenMMException naming the setting to change if the box is too small for the
     * real-space cutoff, the blobs have more than MaxRadii radii, or the memory would exceed the
     * budget; or naming the blob whose position or radius is not finite and positive.
     */
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors = NULL) override;
    /** out = M f = M_real f + M_wave f, for forces f (3 per blob). */
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) override;
    /** out = M_real f. */
    void multiplyRealSpace(const Eigen::VectorXd& f, Eigen::VectorXd& out);
    /** out = M_wave f. */
    void multiplyWaveSpace(const Eigen::VectorXd& f, Eigen::VectorXd& out);
    /**
     * out = a sample of covariance M: M_real^1/2 w (Lanczos on the real-space operator to
     * lanczosTolerance) plus M_wave^1/2 z (exact, in Fourier space). Draws getNumNoiseNormals()
     * standard normals from normal(): first the 3B of w, blob by blob, then the grid's (see
     * sampleWaveSpaceNoise()).
     *
     * @return the real-space Lanczos iteration's outcome and iterations (KrylovSolvers::Result; out
     *         holds an unconverged sample where it did not converge)
     */
    KrylovSolvers::Result sampleNoise(const std::function<double()>& normal, Eigen::VectorXd& out, double lanczosTolerance, int maxLanczosIterations) override;
    /** True: sampleNoise() is exact through the split, a Lanczos on the sparse real-space part only. */
    bool hasOwnNoise() const override {
        return true;
    }
    /** out = M_real^1/2 w for 3B normals w drawn from normal(); returns as sampleNoise(). */
    KrylovSolvers::Result sampleRealSpaceNoise(const std::function<double()>& normal, Eigen::VectorXd& out, double lanczosTolerance,
                                               int maxLanczosIterations);
    /** out = M_wave^1/2 z: six normals per pair of modes k, -k of the half spectrum (mode by mode
     *  in storage order, the plane k_2 = 0 once per pair), 3 (N' - 1) in all, N' being the grid's
     *  points off the Nyquist planes of even grid sizes. */
    void sampleWaveSpaceNoise(const std::function<double()>& normal, Eigen::VectorXd& out);
    /** 3B + 3 (N' - 1): what sampleNoise() draws. */
    long long getNumNoiseNormals() const;
    double getTolerance() const {
        return tolerance;
    }
    /** The splitting in use (chosen at setBlobs() if it was 0). */
    double getSplitting() const;
    /** The largest pair's real-space cutoff, 2 a_max + sqrt(-ln epsilon)/xi (nm). */
    double getRealSpaceCutoff() const;
    /** The grid's points along each box vector. */
    void getGridSize(int size[3]) const;
    /** P: the grid points along each axis that a blob's Gaussian covers. */
    int getSupport() const;
    /** The stored real-space pairs (each in both directions). */
    long long getNumPairs() const;
    /** The bytes the last setBlobs() holds. */
    double getMemoryBytes() const;
    /** The parts of the operator, for a device that applies the same one (CommonPseMobility); after setBlobs(). */
    const PseParameters& getParameters() const;
    const PseRealSpace& getRealSpace() const;
    const PseWaveSpace& getWaveSpace() const;
private:
    void checkBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors) const;
    void checkSize(const Eigen::VectorXd& f) const;
    double tolerance, splitting, memoryBudget, memoryBytes;
    KrylovSolvers::ParallelFor parallel;
    int numBlobs;
    std::unique_ptr<PseParameters> parameters;
    std::unique_ptr<PseRealSpace> real;
    std::unique_ptr<PseWaveSpace> wave;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_POSITIVELY_SPLIT_EWALD_H_*/
