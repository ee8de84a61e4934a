#ifndef HOST_PARTICLE_STORES_H_
#define HOST_PARTICLE_STORES_H_

#include "internal/RigidBodyModel.h"
#include "openmm/OpenMMException.h"
#include <cstdlib>
#include <string>
#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace RigidLangevinPlugin {

/**
 * The size of this machine's last-level cache in bytes, as the C library reports it, or 32 MiB
 * where it reports none.
 */
inline long long hostLastLevelCacheBytes() {
    long long bytes = 0;
#ifdef _SC_LEVEL3_CACHE_SIZE
    bytes = sysconf(_SC_LEVEL3_CACHE_SIZE);
    if (bytes <= 0)
        bytes = sysconf(_SC_LEVEL2_CACHE_SIZE);
#endif
    return (bytes > 0 ? bytes : 32LL << 20);
}

/**
 * How the host step writes particle positions and velocities: RigidBodyModel::chooseParticleStores
 * for this machine's last-level cache, unless the environment variable
 * RIGIDLANGEVIN_HOST_PARTICLE_STORES says "cached" or "streaming" (for tests and benchmarks, which
 * compare the two; "auto" or unset is the default).
 */
inline RigidBodyModel::ParticleStores hostParticleStores(const RigidBodyModel& model) {
    const char* setting = std::getenv("RIGIDLANGEVIN_HOST_PARTICLE_STORES");
    std::string value = (setting == nullptr ? "auto" : setting);
    if (value == "cached")
        return RigidBodyModel::ParticleStores::Cached;
    if (value == "streaming")
        return RigidBodyModel::ParticleStores::Streaming;
    if (value != "auto")
        throw OpenMM::OpenMMException("RigidLangevinIntegrator: the environment variable RIGIDLANGEVIN_HOST_PARTICLE_STORES is \""+value+
                "\"; set it to auto, cached or streaming, or unset it");
    return model.chooseParticleStores(hostLastLevelCacheBytes());
}

} // namespace RigidLangevinPlugin

#endif /*HOST_PARTICLE_STORES_H_*/
