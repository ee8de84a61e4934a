#ifndef RIGID_LANGEVIN_PSE_PARAMETERS_H_
#define RIGID_LANGEVIN_PSE_PARAMETERS_H_

#include "openmm/OpenMMException.h"
#include "openmm/Vec3.h"
#include <string>

namespace RigidLangevinPlugin {

/**
 * The knobs of one positively split Ewald product (PositivelySplitEwald.h), chosen from the
 * tolerance epsilon, the splitting xi, the box and the blobs (HYDRODYNAMIC-INTERACTIONS.md, "Periodic
 * boxes at linear cost"): the real-space cutoff, the grid and the Gaussian that spreads onto it.
 */
struct PseParameters {
    double tolerance;
    double xi;                   // Hasimoto's splitting (1/nm)
    double cutoffBeyondContact;  // blobs i, j interact in real space within a_i + a_j + this
    double realCutoff;           // the largest pair cutoff: 2 a_max + cutoffBeyondContact
    int grid[3];                 // grid points along each box vector
    int support;                 // P: grid points along each axis that a blob spreads onto
    double gaussianWidth;        // sigma (nm) of the spreading Gaussian exp(-r^2/2 sigma^2)
};

/** The most grid points along an axis that a blob's Gaussian covers. */
const int PseMaxSupport = 32;

/** What the blobs are, as the parameters need it. */
struct PseBlobSummary {
    int numBlobs;
    int numRadii;
    double maxRadius, meanRadius;
};

/**
 * What PositivelySplitEwald refuses about a configuration it could take with other settings, with
 * the reason, so that a caller (the integrator's SpectralBlobMobility) names its own settings that
 * would change it. Input that is not usable at all (non-finite, degenerate) is a plain OpenMMException.
 */
class PseRefusal : public OpenMM::OpenMMException {
public:
    enum Reason {
        MemoryBudget,  ///< the grid and real-space pairs would exceed the memory budget
        BoxTooSmall,   ///< no real-space cutoff fits half the box's narrowest width
        TooManyRadii   ///< more distinct blob radii than PositivelySplitEwald::MaxRadii
    };
    PseRefusal(Reason reason, const std::string& message) : OpenMM::OpenMMException(message), reason(reason) {
    }
    Reason getReason() const {
        return reason;
    }
private:
    Reason reason;
};

namespace PseParameterChoice {

/** value to four significant digits, for messages. */
std::string format(double value);

/** The box's widths: distances between opposite faces, 2 pi/|reciprocal_i|. */
void boxWidths(const OpenMM::Vec3 box[3], double widths[3]);

/**
 * The parameters for tolerance, splitting xi (0: the one estimated cheapest) in the box. Throws a
 * PseRefusal naming the setting to change when the box is too small for the real-space cutoff
 * (BoxTooSmall) or the memory would exceed budget (bytes; MemoryBudget).
 */
PseParameters choose(double tolerance, double xi, const OpenMM::Vec3 box[3], const PseBlobSummary& blobs, double budget);

/** The bytes a product with these parameters holds besides the real-space pairs, for blobs. */
double gridBytes(const PseParameters& parameters, const PseBlobSummary& blobs);

/**
 * Whether the real-space pairs are stored in single precision (summed in double) at this tolerance:
 * from 1e-4 up, where float's rounding of a pair's terms (6e-8 of each) stays far below the
 * tolerance (TestPositivelySplitEwald checks 1e-4 against the dense sum); the pairs are read once a
 * product, and in single precision take half the memory and its traffic (benchmark_pse at 1e5 blobs
 * and 1e-3, 2 threads, one run each on a quiet machine: a product 394 +- 16 ms in double, 357 +- 8
 * in single; the peak memory 763 MiB against 452).
 */
bool singlePrecisionPairs(double tolerance);

/** The bytes one real-space pair (one direction) takes at this tolerance. */
double bytesPerPair(double tolerance);

/** Throws the over-budget PseRefusal (MemoryBudget) if the grid and numPairs real-space pairs exceed budget. */
void checkBudget(const PseParameters& parameters, const PseBlobSummary& blobs, double numPairs, double budget);

} // namespace PseParameterChoice
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PSE_PARAMETERS_H_*/
