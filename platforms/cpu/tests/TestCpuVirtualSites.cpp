// tests/TestVirtualSites.h on the CPU platform.
#include "CpuTests.h"
#include "TestVirtualSites.h"
