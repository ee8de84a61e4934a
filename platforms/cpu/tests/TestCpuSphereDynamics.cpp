// tests/TestSphereDynamics.h on the CPU platform.
#include "CpuTests.h"
#include "TestSphereDynamics.h"
