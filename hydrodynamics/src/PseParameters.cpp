#include "internal/PseParameters.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <sstream>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using PseParameterChoice::format;

namespace {

// Each of the four approximations (real-space cutoff, wave-space cutoff, the Gaussian's truncation
// to P points, the grid's aliasing of it) is set to a fraction of the tolerance, so that together
// they stay below it (calibrated against the dense Ewald sum: TestPositivelySplitEwald).
/** F(r) ~ exp(-xi^2 (r - a_i - a_j)^2): cut where that is RealSpaceMargin epsilon. */
const double RealSpaceMargin = 1.0;
/** The grid's Nyquist wave number is NyquistFactor times k_c = 2 xi sqrt(-ln(WaveSpaceMargin epsilon)):
 *  beyond k_c itself, so that the modes of k_c/2 or so, which still carry weight, are aliased
 *  less (with the Nyquist wave number at k_c the error grew as epsilon^3/4). */
const double WaveSpaceMargin = 0.1;
const double NyquistFactor = 1.25;
/** The Gaussian exp(-r^2/2 sigma^2) truncated at half the support, P h/2 (h the smallest distance
 *  between grid planes), leaves erfc(P h/(2 sqrt(2) sigma)); the grid aliases it by
 *  exp(-sigma^2 K^2/2), K the shortest vector of the grid's reciprocal lattice (2 pi/h in a cube).
 *  Both at most GaussianMargin epsilon: P >= 2 m_t m_a/(h K) with m_t = sqrt(2) erfc^-1(that),
 *  m_a = sqrt(2 ln(1/that)) (Lindbo & Tornberg, J. Comput. Phys. 230, 8744 (2011), balance them
 *  the same way). */
const double GaussianMargin = 0.01;
/** The spreading Gaussian stays narrower than Hasimoto's: (2 xi sigma)^2 at most this. */
const double MaxGaussianRatio = 0.8;

// The cost model that chooses xi: seconds per real-space pair, per grid point and log2 of the grid
// (three components, forward and back), per support point (spreading and interpolation), measured
// on one core of the development machine (benchmarks/hydrodynamics/pse_results.md); the optimum
// is broad (a factor 1.5 either side of it costs some 25% more).
const double SecondsPerPair = 3e-9;
const double SecondsPerGridPointLog = 1.5e-9;
const double SecondsPerSupportPoint = 2.8e-9;

const double GiB = 1024.0*1024.0*1024.0;

/** The smallest n' >= n whose prime factors are 2, 3, 5 and 7 (pocketfft's fast lengths). */
int fftSize(int n) {
    for (int m = std::max(n, 1);; m++) {
        int rest = m;
        for (int factor : {2, 3, 5, 7})
            while (rest%factor == 0)
                rest /= factor;
        if (rest == 1)
            return m;
    }
}

/** erfc^-1(y) for small y, by Newton's method. */
double inverseErfc(double y) {
    double x = std::sqrt(-std::log(y));
    for (int i = 0; i < 50; i++)
        x += (std::erfc(x)-y)/(2/std::sqrt(M_PI)*std::exp(-x*x));
    return x;
}

/** The shortest nonzero vector of the grid's reciprocal lattice, sum_d n_d M_d (2 pi inverse_d). */
double shortestAlias(const Vec3 box[3], const int grid[3]) {
    const double volume = box[0].dot(box[1].cross(box[2]));
    Vec3 basis[3];
    for (int d = 0; d < 3; d++)
        basis[d] = box[(d+1)%3].cross(box[(d+2)%3])*(2*M_PI*grid[d]/volume);
    double shortest = 1e300;
    for (int u = -2; u <= 2; u++)
        for (int v = -2; v <= 2; v++)
            for (int w = -2; w <= 2; w++)
                if (u != 0 || v != 0 || w != 0) {
                    Vec3 k = basis[0]*u+basis[1]*v+basis[2]*w;
                    shortest = std::min(shortest, std::sqrt(k.dot(k)));
                }
    return shortest;
}

/** The grid (its Nyquist wave numbers cover k_c in every direction), the support and the Gaussian. */
void chooseGrid(PseParameters& p, const Vec3 box[3]) {
    double widths[3];
    PseParameterChoice::boxWidths(box, widths);
    const double waveCutoff = 2*p.xi*std::sqrt(-std::log(WaveSpaceMargin*p.tolerance));
    const double mTruncation = std::sqrt(2.0)*inverseErfc(GaussianMargin*p.tolerance);
    const double mAliasing = std::sqrt(-2*std::log(GaussianMargin*p.tolerance));
    for (double refine = 1;; refine *= 1.1) {
        double spacing = 1e300;
        for (int d = 0; d < 3; d++) {
            const double length = std::sqrt(box[d].dot(box[d]));
            p.grid[d] = fftSize((int) std::ceil(refine*NyquistFactor*waveCutoff*length/M_PI));
            spacing = std::min(spacing, widths[d]/p.grid[d]);
        }
        const double alias = shortestAlias(box, p.grid);
        p.support = std::min(PseMaxSupport, (int) std::ceil(2*mTruncation*mAliasing/(spacing*alias)-1e-9));
        if (std::min({p.grid[0], p.grid[1], p.grid[2]}) < p.support)
            continue;
        // Between the widest the truncation allows and the narrowest the aliasing does.
        p.gaussianWidth = std::sqrt(0.5*p.support*spacing/mTruncation*mAliasing/alias);
        if (4*p.xi*p.xi*p.gaussianWidth*p.gaussianWidth <= MaxGaussianRatio)
            return;
    }
}

PseParameters parametersFor(double tolerance, double xi, const Vec3 box[3], const PseBlobSummary& blobs) {
    PseParameters p;
    p.tolerance = tolerance;
    p.xi = xi;
    p.cutoffBeyondContact = std::sqrt(-std::log(RealSpaceMargin*tolerance))/xi;
    p.realCutoff = 2*blobs.maxRadius+p.cutoffBeyondContact;
    chooseGrid(p, box);
    return p;
}

double numGridPoints(const PseParameters& p) {
    return (double) p.grid[0]*p.grid[1]*p.grid[2];
}

/** The real-space pairs (both directions) expected for blobs spread evenly through the box. */
double expectedPairs(const PseParameters& p, const Vec3 box[3], const PseBlobSummary& blobs) {
    const double volume = box[0].dot(box[1].cross(box[2]));
    const double reach = 2*blobs.meanRadius+p.cutoffBeyondContact;
    return (double) blobs.numBlobs*blobs.numBlobs/volume*4*M_PI/3*reach*reach*reach;
}

double expectedSeconds(const PseParameters& p, const Vec3 box[3], const PseBlobSummary& blobs) {
    const double n = numGridPoints(p);
    return SecondsPerPair*expectedPairs(p, box, blobs)+SecondsPerGridPointLog*n*std::log2(n)*blobs.numRadii+
           SecondsPerSupportPoint*blobs.numBlobs*std::pow(p.support, 3);
}

} // namespace

std::string PseParameterChoice::format(double value) {
    std::ostringstream out;
    out.precision(4);
    out << value;
    return out.str();
}

void PseParameterChoice::boxWidths(const Vec3 box[3], double widths[3]) {
    const double volume = box[0].dot(box[1].cross(box[2]));
    for (int d = 0; d < 3; d++) {
        Vec3 normal = box[(d+1)%3].cross(box[(d+2)%3]);
        widths[d] = volume/std::sqrt(normal.dot(normal));
    }
}

bool PseParameterChoice::singlePrecisionPairs(double tolerance) {
    return tolerance >= 1e-4;
}

double PseParameterChoice::bytesPerPair(double tolerance) {
    return (singlePrecisionPairs(tolerance) ? 24 : 48);
}

double PseParameterChoice::gridBytes(const PseParameters& p, const PseBlobSummary& blobs) {
    const double n = numGridPoints(p), half = (double) p.grid[0]*p.grid[1]*(p.grid[2]/2+1);
    // The real grid and its spectrum (3 components each), the Fourier factors; with several radii a
    // second spectrum and each radius's sinc(k a) too.
    double bytes = 3*8*n+3*16*half+8*half;
    if (blobs.numRadii > 1)
        bytes += 3*16*half+8*half*blobs.numRadii;
    // Per blob: its Gaussian's factors and grid indices, its cell, offsets and self term.
    return bytes+(double) blobs.numBlobs*(24*p.support+160);
}

void PseParameterChoice::checkBudget(const PseParameters& p, const PseBlobSummary& blobs, double numPairs, double budget) {
    const double grid = gridBytes(p, blobs), pairs = numPairs*bytesPerPair(p.tolerance);
    if (grid+pairs <= budget)
        return;
    throw PseRefusal(PseRefusal::MemoryBudget, "PositivelySplitEwald: "+std::to_string(blobs.numBlobs)+" blobs need "+format((grid+pairs)/GiB)+" GiB (grid "+
            std::to_string(p.grid[0])+" x "+std::to_string(p.grid[1])+" x "+std::to_string(p.grid[2])+" at epsilon "+format(p.tolerance)+": "+
            format(grid/GiB)+" GiB; "+format(numPairs)+" real-space pairs within "+format(p.realCutoff)+" nm at xi "+format(p.xi)+
            " /nm: "+format(pairs/GiB)+" GiB), more than the memory budget of "+format(budget/GiB)+" GiB. Raise the budget "
            "(setMemoryBudget), loosen epsilon, or change xi (a smaller xi shrinks the grid, a larger one the real-space pairs)");
}

PseParameters PseParameterChoice::choose(double tolerance, double xi, const Vec3 box[3], const PseBlobSummary& blobs, double budget) {
    double widths[3];
    boxWidths(box, widths);
    const double halfWidth = 0.5*std::min({widths[0], widths[1], widths[2]});
    // Real-space pairs are taken at their nearest image only, so the cutoff must stay below half
    // the narrowest width: xi above reach/(halfWidth - 2 a_max).
    const double reach = std::sqrt(-std::log(RealSpaceMargin*tolerance));
    if (halfWidth <= 2*blobs.maxRadius)
        throw PseRefusal(PseRefusal::BoxTooSmall, "PositivelySplitEwald: the box (narrowest width "+format(2*halfWidth)+" nm) is too small for blobs of radius "+
                format(blobs.maxRadius)+" nm: its width must exceed 4 radii plus the real-space cutoff (the dense "
                "PeriodicRotnePragerYamakawa needs a width above 4 radii too). Use a bigger box, or smaller blobs (radius under "+format(0.5*halfWidth)+" nm)");
    const double smallestXi = reach/(halfWidth-2*blobs.maxRadius);
    if (xi > 0) {
        if (xi <= smallestXi)
            throw PseRefusal(PseRefusal::BoxTooSmall, "PositivelySplitEwald: the real-space cutoff "+format(2*blobs.maxRadius+reach/xi)+" nm (at epsilon "+format(tolerance)+
                    " and xi "+format(xi)+" /nm) reaches half the box's narrowest width, "+format(halfWidth)+" nm: raise xi above "+
                    format(smallestXi)+" /nm, loosen epsilon, or use a bigger box");
        PseParameters p = parametersFor(tolerance, xi, box, blobs);
        checkBudget(p, blobs, 0, budget);
        return p;
    }
    // The cheapest xi by the cost model among those within the budget; if none is, the smallest.
    PseParameters best, smallest;
    double bestSeconds = -1, smallestBytes = -1;
    const double highest = std::max(3/blobs.meanRadius, smallestXi*1.01);
    for (double x = std::max(smallestXi*1.001, 0.02/blobs.meanRadius); x <= highest; x *= 1.04) {
        PseParameters p = parametersFor(tolerance, x, box, blobs);
        const double bytes = gridBytes(p, blobs)+expectedPairs(p, box, blobs)*bytesPerPair(p.tolerance);
        const double seconds = expectedSeconds(p, box, blobs);
        if (bytes <= budget && (bestSeconds < 0 || seconds < bestSeconds)) {
            best = p;
            bestSeconds = seconds;
        }
        if (smallestBytes < 0 || bytes < smallestBytes) {
            smallest = p;
            smallestBytes = bytes;
        }
    }
    if (bestSeconds < 0)
        checkBudget(smallest, blobs, expectedPairs(smallest, box, blobs), budget);
    return best;
}
