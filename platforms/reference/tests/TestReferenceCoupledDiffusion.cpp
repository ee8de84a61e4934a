// tests/TestCoupledDiffusion.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestCoupledDiffusion.h"
