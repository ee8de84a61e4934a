// tests/TestHydrodynamicInteractions.h on the Reference platform: this runner names the platform (its header
// defines platformUnderTest()); the body, compiled once for every platform, is linked in
// (tests/CMakeLists.txt).
#include "ReferenceTests.h"
