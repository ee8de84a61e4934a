#ifndef RIGIDLANGEVIN_CUDA_TESTS_H_
#define RIGIDLANGEVIN_CUDA_TESTS_H_

// Included first by every runner in this directory: its tests run on the CUDA platform, in the
// precisions each test names. Where the machine has no NVIDIA driver, each runner says so and ctest
// reports it as skipped.
#include "PlatformUnderTest.h"

const RigidBodyTest::PlatformUnderTest& RigidBodyTest::platformUnderTest() {
    static const PlatformUnderTest platform = {"CUDA", "libOpenMMCUDA.so", "libRigidLangevinCUDA.so", true};
    return platform;
}

#endif
