// tests/TestPlatformParity.h on the CUDA platform.
#include "CudaTests.h"
#include "TestPlatformParity.h"
