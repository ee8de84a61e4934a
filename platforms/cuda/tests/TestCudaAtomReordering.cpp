// tests/TestAtomReordering.h on the CUDA platform.
#include "CudaTests.h"
#include "TestAtomReordering.h"
