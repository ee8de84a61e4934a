// tests/TestSphereDynamics.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestSphereDynamics.h"
