// tests/TestCoupledDiffusion.h on the CUDA platform.
#include "CudaTests.h"
#include "TestCoupledDiffusion.h"
