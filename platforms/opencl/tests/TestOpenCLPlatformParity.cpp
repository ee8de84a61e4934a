// tests/TestPlatformParity.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestPlatformParity.h"
