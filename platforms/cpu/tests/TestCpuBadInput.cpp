// tests/TestBadInput.h on the CPU platform.
#include "CpuTests.h"
#include "TestBadInput.h"
