// tests/TestStateAndSystem.h on the CUDA platform.
#include "CudaTests.h"
#include "TestStateAndSystem.h"
