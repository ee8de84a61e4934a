#ifndef RIGIDLANGEVIN_OPENCL_TESTS_H_
#define RIGIDLANGEVIN_OPENCL_TESTS_H_

// Included first by every runner in this directory: its tests run on the OpenCL platform (PoCL on
// machines without a GPU), in the precisions each test names.
#include "PlatformUnderTest.h"

const RigidBodyTest::PlatformUnderTest& RigidBodyTest::platformUnderTest() {
    static const PlatformUnderTest platform = {"OpenCL", "libOpenMMOpenCL.so", "libRigidLangevinOpenCL.so", false};
    return platform;
}

#endif
