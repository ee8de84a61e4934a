// tests/TestEquipartition.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestEquipartition.h"
