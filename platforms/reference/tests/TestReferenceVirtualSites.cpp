// tests/TestVirtualSites.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestVirtualSites.h"
