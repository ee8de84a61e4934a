// tests/TestAtomReordering.h on the CPU platform.
#include "CpuTests.h"
#include "TestAtomReordering.h"
