// tests/TestVirtualSites.h on the CUDA platform.
#include "CudaTests.h"
#include "TestVirtualSites.h"
