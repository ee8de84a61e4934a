/*
 * The Reference kernels are registered as OpenMM registers its own plugins' Reference kernels: on
 * every platform derived from ReferencePlatform that has none yet. A platform a user derives from
 * ReferencePlatform runs the integrator (the same trajectory as Reference); the CPU platform, also
 * derived from it, keeps its own threaded kernel whichever plugin loads first.
 */
#include "CpuTests.h"
#include "RigidBodyTestUtilities.h"
#include "ReferencePlatform.h"
#include <gtest/gtest.h>

extern "C" void registerRigidLangevinReferenceKernelFactories();

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

class DerivedReferencePlatform : public ReferencePlatform {
public:
    const std::string& getName() const {
        static const std::string name = "DerivedReference";
        return name;
    }
};

/** Positions after 50 steps of two asymmetric bodies at a viscosity of 0.01 amu/(nm ps), seed 5. */
std::vector<Vec3> trajectoryEnd(Platform& platform) {
    System system;
    RigidLangevinIntegrator integrator(300, 0.01, 0.002);
    integrator.setRandomNumberSeed(5);
    std::vector<Vec3> positions = addBodiesInARow(system, integrator, asymmetricBody(), 2, 0.1);
    Context context(system, integrator, platform);
    context.setPositions(positions);
    context.setVelocitiesToTemperature(300, 3);
    integrator.step(50);
    return context.getState(State::Positions).getPositions();
}

} // namespace

TEST(KernelRegistration, PlatformsDerivedFromReferenceRunTheReferenceKernels) {
    Platform::registerPlatform(new DerivedReferencePlatform());
    Platform& derived = Platform::getPlatformByName("DerivedReference");
    ASSERT_FALSE(derived.supportsKernels({IntegrateRigidLangevinStepKernel::Name()}));
    registerRigidLangevinReferenceKernelFactories();
    ASSERT_TRUE(derived.supportsKernels({IntegrateRigidLangevinStepKernel::Name()}));
    std::vector<Vec3> onDerived = trajectoryEnd(derived), onReference = trajectoryEnd(Platform::getPlatformByName("Reference"));
    for (int i = 0; i < (int) onDerived.size(); i++)
        for (int k = 0; k < 3; k++)
            EXPECT_EQ(onReference[i][k], onDerived[i][k]);
}

TEST(KernelRegistration, TheCpuPlatformKeepsItsOwnKernel) {
    // Registering the Reference kernels again, after the CPU plugin (as TestMain did),
    // must not take the CPU platform's kernel: with its own random number streams it follows another
    // trajectory than Reference from the same seed, where the Reference kernel would follow the same.
    registerRigidLangevinReferenceKernelFactories();
    std::vector<Vec3> onCpu = trajectoryEnd(Platform::getPlatformByName("CPU")), onReference = trajectoryEnd(Platform::getPlatformByName("Reference"));
    double largest = 0;
    for (int i = 0; i < (int) onCpu.size(); i++)
        largest = std::max(largest, std::sqrt((onCpu[i]-onReference[i]).dot(onCpu[i]-onReference[i])));
    EXPECT_GT(largest, 1e-3);
}
