#ifndef RIGIDLANGEVIN_CPU_TESTS_H_
#define RIGIDLANGEVIN_CPU_TESTS_H_

// Included first by every runner in this directory: its tests run on the CPU platform (OpenMM's
// libOpenMMCPU and this plugin's libRigidLangevinCPU)..
#include "PlatformUnderTest.h"

const RigidBodyTest::PlatformUnderTest& RigidBodyTest::platformUnderTest() {
    static const PlatformUnderTest platform = {"CPU", "libOpenMMCPU.so", "libRigidLangevinCPU.so", false};
    return platform;
}

#endif
