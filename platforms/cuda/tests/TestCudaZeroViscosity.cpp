// tests/TestZeroViscosity.h on the CUDA platform.
#include "CudaTests.h"
#include "TestZeroViscosity.h"
