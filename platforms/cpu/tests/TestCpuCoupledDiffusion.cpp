// tests/TestCoupledDiffusion.h on the CPU platform.
#include "CpuTests.h"
#include "TestCoupledDiffusion.h"
