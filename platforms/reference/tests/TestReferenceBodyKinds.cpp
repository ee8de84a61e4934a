// tests/TestBodyKinds.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestBodyKinds.h"
