// Two rigid water-shaped bodies in implicit water: the mean temperature over 2000 steps.
#include "OpenMM.h"
#include "RigidLangevinIntegrator.h"
#include <cstdio>

// The plugin's Reference kernels, registered by the program itself (a program that loads OpenMM's
// plugin directory with Platform::loadPluginsFromDirectory gets every platform's kernels from there).
extern "C" void registerRigidLangevinReferenceKernelFactories();

int main() {
    registerRigidLangevinReferenceKernelFactories();
    OpenMM::System system;
    RigidLangevinPlugin::RigidLangevinIntegrator integrator(300.0, 536.0, 0.002);  // K, amu/(nm ps) = 0.89 cP, ps
    integrator.setRandomNumberSeed(1);                                            // the same run every time
    std::vector<OpenMM::Vec3> positions;
    for (int b = 0; b < 2; b++) {
        int o = system.addParticle(15.999), h1 = system.addParticle(1.008), h2 = system.addParticle(1.008);
        integrator.addRigidBody({o, h1, h2});
        integrator.setParticleRadius(o, 0.15);  // hydrodynamic radii (nm): the body's 6x6 friction
        integrator.setParticleRadius(h1, 0.1);
        integrator.setParticleRadius(h2, 0.1);
        positions.insert(positions.end(), {OpenMM::Vec3(b, 0, 0), OpenMM::Vec3(b+0.09572, 0, 0), OpenMM::Vec3(b-0.024, 0.0927, 0)});
    }
    OpenMM::Context context(system, integrator, OpenMM::Platform::getPlatformByName("Reference"));
    context.setPositions(positions);
    context.setVelocitiesToTemperature(300.0, 1);
    double sum = 0;  // 12 degrees of freedom fluctuate by 40% a sample: average 2000 steps
    for (int i = 0; i < 2000; i++) {
        integrator.step(1);
        sum += integrator.computeSystemTemperature();
    }
    std::printf("degrees of freedom %d, mean temperature %.1f K\n", integrator.getNumDegreesOfFreedom(), sum/2000);
    return 0;
}
