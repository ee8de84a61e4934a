// tests/TestBadInput.h on the CUDA platform.
#include "CudaTests.h"
#include "TestBadInput.h"
