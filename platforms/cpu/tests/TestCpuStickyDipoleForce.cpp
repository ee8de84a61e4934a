// tests/TestStickyDipoleForce.h on the CPU platform.
#include "CpuTests.h"
#include "TestStickyDipoleForce.h"
