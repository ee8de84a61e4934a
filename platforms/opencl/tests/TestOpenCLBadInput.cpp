// tests/TestBadInput.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestBadInput.h"
