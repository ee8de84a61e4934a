// tests/TestStateAndSystem.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestStateAndSystem.h"
