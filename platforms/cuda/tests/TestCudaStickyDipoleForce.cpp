// tests/TestStickyDipoleForce.h on the CUDA platform.
#include "CudaTests.h"
#include "TestStickyDipoleForce.h"
