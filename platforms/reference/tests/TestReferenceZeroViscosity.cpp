// tests/TestZeroViscosity.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestZeroViscosity.h"
