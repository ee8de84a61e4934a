// tests/TestSphereDynamics.h on the CUDA platform.
#include "CudaTests.h"
#include "TestSphereDynamics.h"
