// tests/TestSinglePrecision.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestSinglePrecision.h"
