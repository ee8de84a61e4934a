// tests/TestAtomReordering.h on the OpenCL platform.
#include "OpenCLTests.h"
#include "TestAtomReordering.h"
