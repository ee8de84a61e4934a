// tests/TestBodyKinds.h on the CUDA platform.
#include "CudaTests.h"
#include "TestBodyKinds.h"
