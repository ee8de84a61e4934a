#ifndef RIGIDLANGEVIN_REFERENCE_TESTS_H_
#define RIGIDLANGEVIN_REFERENCE_TESTS_H_

// Included first by every runner in this directory: its tests run on the Reference platform: double precision, the definition of correct.
#include "PlatformUnderTest.h"

const RigidBodyTest::PlatformUnderTest& RigidBodyTest::platformUnderTest() {
    static const PlatformUnderTest platform = {"Reference", "", "", false};
    return platform;
}

#endif
