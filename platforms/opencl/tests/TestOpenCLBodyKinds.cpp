// tests/TestBodyKinds.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestBodyKinds.h"
