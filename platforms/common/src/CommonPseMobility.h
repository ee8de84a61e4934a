#ifndef COMMON_PSE_MOBILITY_H_
#define COMMON_PSE_MOBILITY_H_

#include "internal/SpectralBlobMobility.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/common/FFT3D.h"
#include <string>

namespace RigidLangevinPlugin {

class PseGaussianGrid;
class PseRealSpace;
class PseWaveSpace;
struct PseParameters;

/**
 * The spectral solver's products in a periodic box on the device of a common compute platform: the
 * positively split Ewald product (kernels/pseMobility.cc), with the FFTs by OpenMM's createFFT.
 * The host's PositivelySplitEwald (SpectralBlobMobility, this class's base) still chooses the
 * parameters, finds the real-space pairs with its cell list and computes their terms, each blob's
 * Gaussian factors and the Fourier factors once per setBlobs(), on the platform's threads; they are
 * uploaded then, and every product runs on the device: real-space rows, spreading by fixed-point
 * atomic adds, three FFTs per radius group each way, the Fourier factors, interpolation. The solver's
 * Krylov iterations run on the host, as for the other products, so that every platform takes the
 * same steps; a product moves the force and the velocity (3 doubles a blob each way). The PSE's own
 * noise (sampleNoise(), RigidBrownianIntegrator's, exact through the split) is the base class's, on
 * the host: a Lanczos on the sparse real-space part and one transform of the grid.
 *
 * Precision: the real-space pairs as the host stores them (float from epsilon 1e-4 up), summed in
 * double; the grid, the FFTs and interpolation in the context's precision (float in single and
 * mixed). Where that is float and the tolerance is tighter than SinglePrecisionTolerance (float's
 * rounding in the FFTs would reach it), where in a triclinic box the Gaussians' factors would near
 * float's range, where the device's FFT cannot take the grid, or where the device has no double
 * precision (its sums are in double), the products are the host's (the base class's), so that the
 * tolerance holds on every device; so too where the arrays outgrow int counts (fitsIntCounts()).
 */
class CommonPseMobility : public SpectralBlobMobility {
public:
    CommonPseMobility(OpenMM::ComputeContext& cc, const std::string& integratorName, const KrylovSolvers::ParallelFor& parallel);
    void setTolerance(double tolerance) override;
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors = NULL) override;
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) override;
    /** Whether the products since the last setBlobs() run on the device (else on the host). */
    bool isOnDevice() const {
        return onDevice;
    }
    /** In float, the tightest tolerance the device's products take: their rounding (the grid, FFTs and interpolation in float) was
     *  8e-8 of the host's product (TestOpenCLDeviceBlobMobility, PoCL), over 100 times below. */
    static constexpr double SinglePrecisionTolerance = 1e-5;
    /**
     * Whether a configuration's uploads and kernel ranges count in int, as OpenMM's uploadSubArray()
     * and the kernels' indices do: pairWords 4-byte words of real-space pairs, a grid of
     * grid[0]*grid[1]*grid[2] points a component, numGroups radius groups, numBlobs blobs each spread
     * over support^2 lines. Beyond them (about 3.5e8 pairs in float, a grid of 890^3) the products are
     * the host's.
     */
    static bool fitsIntCounts(size_t pairWords, const int grid[3], int numGroups, size_t numBlobs, int support);
private:
    /** The grid's arrays and FFT for these parameters (kept while the grid is the same size). */
    void prepareGrid(const PseParameters& parameters, int numGroups);
    void uploadRealSpace(const PseRealSpace& real);
    void uploadGaussians(const PseGaussianGrid& gaussians, int support);
    void uploadWaveFactors(const PseWaveSpace& wave, int numGroups);
    /** The kernels, compiled for real-space pairs in double or single precision. */
    void compileKernels(bool doublePairs);
    /** Spread group g's forces (fixed point at scale) and transform them into spectrum. */
    void spreadAndTransform(int g, double scale);
    /** Transform spectrum back and add group g's interpolated velocities. */
    void transformBackAndInterpolate(int g);
    OpenMM::ComputeContext& cc;
    double tolerance;
    bool onDevice, doublePairs, compiled, triclinic;
    int numBlobs, numGroups, support, grid[3];
    double maxWeight;  ///< the Gaussian's peak, the largest weight a blob gives a grid point: bounds the fixed-point sums
    std::vector<int> groupStart;
    OpenMM::FFT3D fft;
    OpenMM::ComputeKernel gatherKernel, rowsKernel, spreadKernel, toRealKernel, scaleKernel, factorsKernel, interpolateKernel;
    OpenMM::ComputeArray order, rowStart, pairs, self, force, sortedForce, velocity;
    OpenMM::ComputeArray groupBlobs, base, factors, cross, fourierFactor, sincs;
    OpenMM::ComputeArray accumulator, realGrid[3], spectrum[3], summed[3];
    OpenMM::Vec3 reciprocal[3];
};

} // namespace RigidLangevinPlugin

#endif /*COMMON_PSE_MOBILITY_H_*/
