// tests/TestBadInput.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestBadInput.h"
