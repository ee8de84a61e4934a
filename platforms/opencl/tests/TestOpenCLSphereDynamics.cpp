// tests/TestSphereDynamics.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestSphereDynamics.h"
