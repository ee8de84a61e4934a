#ifndef RIGID_LANGEVIN_GAUSSIAN_RANDOM_H_
#define RIGID_LANGEVIN_GAUSSIAN_RANDOM_H_

#include "internal/windowsExportRigidLangevin.h"
#include "sfmt/SFMT.h"
#include <iosfwd>
#include <memory>

namespace RigidLangevinPlugin {

/**
 * Standard normal random numbers from OpenMM's SFMT generator (polar Box-Muller, the method of
 * OpenMM's own reference platform), with a state that can be checkpointed exactly.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN GaussianRandom {
public:
    /** Seed the generator; 0 picks a seed from the operating system, as OpenMM does. */
    explicit GaussianRandom(int seed = 0);
    double next();
    void createCheckpoint(std::ostream& stream);
    void loadCheckpoint(std::istream& stream);
private:
    std::unique_ptr<OpenMM_SFMT::SFMT> sfmt;
    bool haveSpare;
    double spare;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_GAUSSIAN_RANDOM_H_*/
