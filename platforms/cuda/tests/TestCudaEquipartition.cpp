// tests/TestEquipartition.h on the CUDA platform.
#include "CudaTests.h"
#include "TestEquipartition.h"
