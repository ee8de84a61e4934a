// tests/TestHydrodynamicInteractions.h on the CPU platform: this runner names the platform (its header
// defines platformUnderTest()); the body, compiled once for every platform, is linked in
// (tests/CMakeLists.txt).
#include "CpuTests.h"
