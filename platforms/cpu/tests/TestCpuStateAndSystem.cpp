// tests/TestStateAndSystem.h on the CPU platform.
#include "CpuTests.h"
#include "TestStateAndSystem.h"
