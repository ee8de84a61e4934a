#include "CommonPseMobility.h"
#include "CommonArrays.h"
#include "CommonRigidLangevinKernelSources.h"
#include "internal/PseParameters.h"
#include "internal/PseRealSpace.h"
#include "internal/PseWaveSpace.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
#include <algorithm>
#include <cmath>
#include <limits>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

// The kernel's PsePair has the host's layout: an int, then five reals at their natural alignment.
static_assert(sizeof(PseRealSpace::Pair<float>) == 24 && sizeof(PseRealSpace::Pair<double>) == 48, "PsePair's layout");

namespace {

void setArgs(ComputeKernel&, int) {
}

/** The kernel's arguments from index on, in order (arrays by reference, scalars by their exact type). */
template <class First, class... Rest>
void setArgs(ComputeKernel& kernel, int index, First&& first, Rest&&... rest) {
    kernel->setArg(index, first);
    setArgs(kernel, index+1, std::forward<Rest>(rest)...);
}

ComputeKernel createKernel(ComputeProgram& program, const char* name, int numArgs) {
    ComputeKernel kernel = program->createKernel(name);
    for (int k = 0; k < numArgs; k++)
        kernel->addArg();
    return kernel;
}

/** The bytes of the real-space pairs as the host stores them (float or double terms). */
size_t pairBytes(const PseRealSpace& real) {
    return real.getSinglePairs().size()*sizeof(PseRealSpace::Pair<float>)+real.getDoublePairs().size()*sizeof(PseRealSpace::Pair<double>);
}

/** values in the context's real type (float unless in double precision), for upload. */
vector<char> asReal(const vector<double>& values, bool useDouble) {
    vector<char> bytes(values.size()*(useDouble ? sizeof(double) : sizeof(float)));
    if (useDouble)
        std::copy(values.begin(), values.end(), (double*) bytes.data());
    else
        std::copy(values.begin(), values.end(), (float*) bytes.data());
    return bytes;
}

/**
 * Whether the Gaussians' factors hold in float: in a triclinic box the shared factors (n0, n1, n2)
 * grow as exp(|h_d . h_e| n_d n_e/sigma^2) and the per-axis factors shrink to compensate. The most
 * skewed box of OpenMM's reduced form at tolerance 1e-5 (the tightest float takes) reached 4.7e29
 * and its products stayed within 1e-6 of the host's (TestOpenCLDeviceBlobMobility); beyond
 * MaxSingleCrossFactor float's range (3.4e38) comes near.
 */
bool fitsSinglePrecision(const PseGaussianGrid& gaussians) {
    const double MaxSingleCrossFactor = 1e30;
    const vector<double> cross = gaussians.getCrossFactors();
    return cross.empty() || *std::max_element(cross.begin(), cross.end()) <= MaxSingleCrossFactor;
}

} // namespace

CommonPseMobility::CommonPseMobility(ComputeContext& cc, const std::string& integratorName, const KrylovSolvers::ParallelFor& parallel) :
        SpectralBlobMobility(integratorName, parallel), cc(cc), tolerance(0), onDevice(false), doublePairs(false), compiled(false), triclinic(false),
        numBlobs(0), numGroups(0), support(0), grid{0, 0, 0}, maxWeight(0) {
}

void CommonPseMobility::setTolerance(double tolerance) {
    SpectralBlobMobility::setTolerance(tolerance);
    this->tolerance = tolerance;
}

void CommonPseMobility::setBlobs(const vector<Vec3>& positions, const vector<double>& radii, const Vec3* boxVectors) {
    SpectralBlobMobility::setBlobs(positions, radii, boxVectors);
    numBlobs = positions.size();
    // The kernels sum in double (and read the forces and Fourier factors in it): a device without it keeps the host's products.
    onDevice = (numBlobs > 0 && cc.getSupportsDoublePrecision() && (cc.getUseDoublePrecision() || tolerance >= SinglePrecisionTolerance));
    if (!onDevice)
        return;
    const PositivelySplitEwald& pse = getProduct();
    const PseParameters& p = pse.getParameters();
    for (int d = 0; d < 3; d++)
        if (cc.findLegalFFTDimension(p.grid[d]) != p.grid[d]) {
            onDevice = false;
            return;
        }
    const PseWaveSpace& wave = pse.getWaveSpace();
    numGroups = wave.getGaussians().getGroupStart().size()-1;
    if ((!cc.getUseDoublePrecision() && !fitsSinglePrecision(wave.getGaussians())) ||
            !fitsIntCounts(pairBytes(pse.getRealSpace())/4, p.grid, numGroups, numBlobs, p.support)) {
        onDevice = false;
        return;
    }
    ContextSelector selector(cc);
    prepareGrid(p, numGroups);
    fitArray(cc, force, 3*numBlobs, sizeof(double), "pseForce", ArrayFit::Exact);
    fitArray(cc, sortedForce, 3*numBlobs, sizeof(double), "pseSortedForce", ArrayFit::Exact);
    fitArray(cc, velocity, 3*numBlobs, sizeof(double), "pseVelocity", ArrayFit::Exact);
    uploadRealSpace(pse.getRealSpace());
    uploadGaussians(wave.getGaussians(), p.support);
    // The largest weight a blob gives a grid point, the Gaussian's peak (the factors' bound is far looser in a triclinic box).
    maxWeight = std::pow(2*M_PI*p.gaussianWidth*p.gaussianWidth, -1.5);
    uploadWaveFactors(wave, numGroups);
    compileKernels(!PseParameterChoice::singlePrecisionPairs(p.tolerance));
}

bool CommonPseMobility::fitsIntCounts(size_t pairWords, const int grid[3], int numGroups, size_t numBlobs, int support) {
    const size_t most = std::numeric_limits<int>::max();
    const size_t points = (size_t) grid[0]*grid[1]*grid[2], modes = (size_t) grid[0]*grid[1]*(grid[2]/2+1);
    // The grid's three components share one accumulator; the sincs hold one spectrum a radius group.
    return pairWords <= most && 3*points <= most && numGroups*modes <= most && 3*numBlobs <= most && numBlobs*support*support <= most;
}

void CommonPseMobility::prepareGrid(const PseParameters& p, int groups) {
    const bool sameGrid = (fft && std::equal(grid, grid+3, p.grid));
    std::copy(p.grid, p.grid+3, grid);
    const size_t points = (size_t) grid[0]*grid[1]*grid[2], modes = (size_t) grid[0]*grid[1]*(grid[2]/2+1);
    // The FFT's arrays are complex (its input is its workspace), in the context's precision.
    const int complexSize = 2*(cc.getUseDoublePrecision() ? sizeof(double) : sizeof(float));
    if (fitArray(cc, accumulator, 3*points, sizeof(long long), "pseAccumulator", ArrayFit::AtLeast))
        cc.clearBuffer(accumulator);
    for (int c = 0; c < 3; c++) {
        fitArray(cc, realGrid[c], points, complexSize, "pseRealGrid", ArrayFit::AtLeast);
        fitArray(cc, spectrum[c], points, complexSize, "pseSpectrum", ArrayFit::AtLeast);
        fitArray(cc, summed[c], groups > 1 ? modes : 1, complexSize, "pseSummedSpectrum", ArrayFit::AtLeast);
    }
    if (!sameGrid)
        fft = cc.createFFT(grid[0], grid[1], grid[2], true);
}

void CommonPseMobility::uploadRealSpace(const PseRealSpace& real) {
    const vector<int>& sortedOrder = real.getOrder();
    fitArray(cc, order, numBlobs, sizeof(int), "pseOrder", ArrayFit::AtLeast);
    order.uploadSubArray(sortedOrder.data(), 0, numBlobs);
    fitArray(cc, self, numBlobs, sizeof(double), "pseSelf", ArrayFit::AtLeast);
    self.uploadSubArray(real.getSelf().data(), 0, numBlobs);
    fitArray(cc, rowStart, numBlobs+1, sizeof(long long), "pseRowStart", ArrayFit::AtLeast);
    rowStart.uploadSubArray(real.getRowStart().data(), 0, numBlobs+1);
    // The pairs as 4-byte words, whichever their precision, so that the array's type never changes.
    const void* data = (real.getSinglePairs().empty() ? (const void*) real.getDoublePairs().data() : (const void*) real.getSinglePairs().data());
    const size_t bytes = pairBytes(real);
    fitArray(cc, pairs, bytes/4, 4, "pseRealSpacePairs", ArrayFit::AtLeast);
    if (bytes > 0)
        pairs.uploadSubArray(data, 0, bytes/4);
}

void CommonPseMobility::uploadGaussians(const PseGaussianGrid& gaussians, int p) {
    support = p;
    groupStart = gaussians.getGroupStart();
    fitArray(cc, groupBlobs, numBlobs, sizeof(int), "pseGroupBlobs", ArrayFit::AtLeast);
    groupBlobs.uploadSubArray(gaussians.getGroupBlobs().data(), 0, numBlobs);
    fitArray(cc, base, 3*numBlobs, sizeof(int), "pseSupportBase", ArrayFit::AtLeast);
    base.uploadSubArray(gaussians.getBase().data(), 0, 3*numBlobs);
    const bool useDouble = cc.getUseDoublePrecision();
    const int realSize = (useDouble ? sizeof(double) : sizeof(float));
    const vector<double>& w = gaussians.getFactors();
    fitArray(cc, factors, w.size(), realSize, "pseGaussianFactors", ArrayFit::AtLeast);
    factors.uploadSubArray(asReal(w, useDouble).data(), 0, w.size());
    const vector<double> shared = gaussians.getCrossFactors();
    triclinic = !shared.empty();
    fitArray(cc, cross, shared.size(), realSize, "pseCrossFactors", ArrayFit::AtLeast);
    if (!shared.empty())
        cross.uploadSubArray(asReal(shared, useDouble).data(), 0, shared.size());
}

void CommonPseMobility::uploadWaveFactors(const PseWaveSpace& wave, int groups) {
    const vector<double>& factor = wave.getFactors();
    fitArray(cc, fourierFactor, factor.size(), sizeof(double), "pseFourierFactors", ArrayFit::AtLeast);
    fourierFactor.uploadSubArray(factor.data(), 0, factor.size());
    const vector<double>& groupSincs = wave.getSincs();
    fitArray(cc, sincs, groups > 1 ? groupSincs.size() : 1, sizeof(double), "pseSincs", ArrayFit::AtLeast);
    if (groups > 1)
        sincs.uploadSubArray(groupSincs.data(), 0, groupSincs.size());
    for (int d = 0; d < 3; d++)
        reciprocal[d] = wave.getReciprocal(d);
}

void CommonPseMobility::compileKernels(bool pairsInDouble) {
    if (compiled && pairsInDouble == doublePairs)
        return;
    ComputeProgram program = cc.compileProgram(CommonRigidLangevinKernelSources::pseMobility, {{"PSE_DOUBLE_PAIRS", pairsInDouble ? "1" : "0"}});
    gatherKernel = createKernel(program, "pseGatherForces", 4);
    rowsKernel = createKernel(program, "pseRealSpaceRows", 7);
    spreadKernel = createKernel(program, "pseSpread", 14);
    toRealKernel = createKernel(program, "pseGridToReal", 6);
    scaleKernel = createKernel(program, "pseScaleSpectrum", 10);
    factorsKernel = createKernel(program, "pseApplyFactors", 16);
    interpolateKernel = createKernel(program, "pseInterpolate", 15);
    doublePairs = pairsInDouble;
    compiled = true;
}

void CommonPseMobility::spreadAndTransform(int g, double scale) {
    const int first = groupStart[g], count = groupStart[g+1]-first;
    const int points = grid[0]*grid[1]*grid[2], modes = grid[0]*grid[1]*(grid[2]/2+1);
    setArgs(spreadKernel, 0, first, count, support, grid[0], grid[1], grid[2], groupBlobs, base, factors, cross,
            (int) triclinic, force, scale, accumulator);
    spreadKernel->execute(count*support*support);
    setArgs(toRealKernel, 0, points, accumulator, 1/scale, realGrid[0], realGrid[1], realGrid[2]);
    toRealKernel->execute(points);
    for (int c = 0; c < 3; c++)
        fft->execFFT(realGrid[c], spectrum[c], true);
    if (numGroups > 1) {
        setArgs(scaleKernel, 0, modes, sincs, g, (int) (g > 0), spectrum[0], spectrum[1], spectrum[2], summed[0], summed[1], summed[2]);
        scaleKernel->execute(modes);
    }
}

void CommonPseMobility::transformBackAndInterpolate(int g) {
    const int first = groupStart[g], count = groupStart[g+1]-first;
    if (numGroups > 1) {
        const int modes = grid[0]*grid[1]*(grid[2]/2+1);
        setArgs(scaleKernel, 0, modes, sincs, g, 0, summed[0], summed[1], summed[2], spectrum[0], spectrum[1], spectrum[2]);
        scaleKernel->execute(modes);
    }
    for (int c = 0; c < 3; c++)
        fft->execFFT(spectrum[c], realGrid[c], false);
    setArgs(interpolateKernel, 0, first, count, support, grid[0], grid[1], grid[2], groupBlobs, base, factors, cross,
            (int) triclinic, realGrid[0], realGrid[1], realGrid[2], velocity);
    interpolateKernel->execute(count);
}

void CommonPseMobility::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    if (!onDevice) {
        SpectralBlobMobility::multiply(f, out);
        return;
    }
    if (f.size() != 3*numBlobs)
        throw OpenMMException("CommonPseMobility: a product with "+std::to_string(f.size())+" force components for "+std::to_string(numBlobs)+" blobs");
    ContextSelector selector(cc);
    force.uploadSubArray(f.data(), 0, 3*numBlobs);
    setArgs(gatherKernel, 0, numBlobs, order, force, sortedForce);
    gatherKernel->execute(numBlobs);
    setArgs(rowsKernel, 0, numBlobs, order, rowStart, pairs, self, sortedForce, velocity);
    rowsKernel->execute(numBlobs);
    // Fixed point at a power of two that keeps every grid point's sum, at most maxWeight sum |f|, below 2^62.
    const double bound = maxWeight*f.lpNorm<1>();
    if (bound > 0) {
        int exponent;
        std::frexp(bound, &exponent);
        const double scale = std::ldexp(1.0, 62-exponent);
        for (int g = 0; g < numGroups; g++)
            spreadAndTransform(g, scale);
        ComputeArray* u = (numGroups > 1 ? summed : spectrum);
        setArgs(factorsKernel, 0, grid[0], grid[1], grid[2]/2+1, fourierFactor, reciprocal[0][0], reciprocal[0][1], reciprocal[0][2],
                reciprocal[1][0], reciprocal[1][1], reciprocal[1][2], reciprocal[2][0], reciprocal[2][1], reciprocal[2][2], u[0], u[1], u[2]);
        factorsKernel->execute(grid[0]*grid[1]*(grid[2]/2+1));
        for (int g = 0; g < numGroups; g++)
            transformBackAndInterpolate(g);
    }
    out.resize(3*numBlobs);
    velocity.download(out.data());
}
