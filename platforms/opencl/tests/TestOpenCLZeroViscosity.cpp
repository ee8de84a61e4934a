// tests/TestZeroViscosity.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestZeroViscosity.h"
