// tests/TestBodyKinds.h on the CPU platform.
#include "CpuTests.h"
#include "TestBodyKinds.h"
