// tests/TestStickyDipoleForce.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestStickyDipoleForce.h"
