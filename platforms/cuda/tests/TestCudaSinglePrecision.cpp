// tests/TestSinglePrecision.h on the CUDA platform.
#include "CudaTests.h"
#include "TestSinglePrecision.h"
