// tests/TestCoupledDiffusion.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestCoupledDiffusion.h"
