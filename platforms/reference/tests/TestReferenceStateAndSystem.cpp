// tests/TestStateAndSystem.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestStateAndSystem.h"
