// tests/TestPlatformParity.h on the CPU platform.
#include "CpuTests.h"
#include "TestPlatformParity.h"
