#ifndef RIGIDLANGEVIN_CPU_TESTS_H_
#define RIGIDLANGEVIN_CPU_TESTS_H_

// Included first by every runner in this directory: its tests run on the CPU platform (OpenMM's
// libOpenMMCPU and this plugin's libRigidLangevinCPU)..
#include "PlatformUnderTest.h"
#include <cstdlib>
#include <string>

const RigidBodyTest::PlatformUnderTest& RigidBodyTest::platformUnderTest() {
    static const PlatformUnderTest platform = {"CPU", "libOpenMMCPU.so", "libRigidLangevinCPU.so", false};
    return platform;
}

/**
 * Whether this run is one of ctest's TestCpu*Baseline: a runner under QEMU as a processor without
 * AVX2, which sets RIGIDLANGEVIN_HOST_CLONES=compare (CMakeLists.txt in this directory), so that
 * the host code's baseline builds run.
 */
inline bool emulatingBaselineBuilds() {
    const char* mode = std::getenv("RIGIDLANGEVIN_HOST_CLONES");
    return mode != nullptr && std::string(mode) == "compare";
}

#endif
