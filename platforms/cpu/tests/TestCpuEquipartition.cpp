// tests/TestEquipartition.h on the CPU platform.
#include "CpuTests.h"
#include "TestEquipartition.h"
