// tests/TestEquipartition.h on the Reference platform.
#include "ReferenceTests.h"
#include "TestEquipartition.h"

// The measurement's own check, run once, on the platform that defines correct.
TEST(EquipartitionCheck, DetectsAWrongTemperature) {
    // The same measurement must see a 5% error: run at 315 K and compare with 300 K.
    Covariance run = measureCovariance(platformConfigs()[0], RigidLangevinIntegrator::ExactFlow, 1.0, 800, 1, 300);
    double factor = 315.0/300.0;
    int failures = 0;
    for (int i = 0; i < 6; i++)
        if (std::abs(run.mean(i, i)*factor-1.0) > 4*run.error(i, i))
            failures++;
    EXPECT_EQ(6, failures);
}
