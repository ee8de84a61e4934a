#ifndef RIGIDLANGEVIN_PLATFORM_UNDER_TEST_H_
#define RIGIDLANGEVIN_PLATFORM_UNDER_TEST_H_

#include <string>

namespace RigidBodyTest {

/**
 * The platform a test executable runs on. The shared test bodies (tests/Test*.h) are compiled once
 * and linked into one runner per platform (platforms/<platform>/tests/Test<Platform>*.cpp), which
 * includes its platform's header (ReferenceTests.h, CpuTests.h, OpenCLTests.h, CudaTests.h)
 * defining this function; the bodies ask it at run time. TestMain.cpp loads the platform and this
 * plugin's kernels for it before any test runs. Alone in this header so that a runner compiles in
 * a moment.
 */
struct PlatformUnderTest {
    std::string name;           ///< OpenMM's name of the platform
    std::string openmmLibrary;  ///< OpenMM's plugin library providing it ("" for Reference, built into libOpenMM)
    std::string pluginLibrary;  ///< this plugin's kernel library for it ("" for Reference, linked into the tests)
    bool mayBeMissing;          ///< only CUDA: absent where the machine has no NVIDIA driver, then reported skipped
};

const PlatformUnderTest& platformUnderTest();

} // namespace RigidBodyTest

#endif
