// tests/TestZeroViscosity.h on the CPU platform.
#include "CpuTests.h"
#include "TestZeroViscosity.h"
