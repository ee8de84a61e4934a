// tests/TestVirtualSites.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestVirtualSites.h"
