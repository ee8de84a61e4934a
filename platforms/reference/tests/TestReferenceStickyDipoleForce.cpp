// tests/TestStickyDipoleForce.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestStickyDipoleForce.h"
