#include "CpuRigidLangevinKernelFactory.h"
#include "CpuRigidLangevinKernels.h"
#include "CpuPlatform.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

// Called through both entry points below. A plugin calls no exported function of its own: with
// several plugins loaded, the dynamic linker could bind such a call to another plugin's.
void registerFactories() {
    // The CPU platform is a plugin of its own; without it there is nothing to register on.
    for (int i = 0; i < Platform::getNumPlatforms(); i++) {
        Platform& platform = Platform::getPlatform(i);
        if (platform.getName() == "CPU") {
            platform.registerKernelFactory(IntegrateRigidLangevinStepKernel::Name(), new CpuRigidLangevinKernelFactory());
            platform.registerKernelFactory(CalcStickyDipoleForceKernel::Name(), new CpuRigidLangevinKernelFactory());
        }
    }
}

} // namespace

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    registerFactories();
}

extern "C" OPENMM_EXPORT void registerRigidLangevinCpuKernelFactories() {
    registerFactories();
}

KernelImpl* CpuRigidLangevinKernelFactory::createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const {
    ReferencePlatform::PlatformData& data = *static_cast<ReferencePlatform::PlatformData*>(context.getPlatformData());
    CpuPlatform::PlatformData& cpuData = CpuPlatform::getPlatformData(context);
    if (name == IntegrateRigidLangevinStepKernel::Name())
        return new CpuIntegrateRigidLangevinStepKernel(name, platform, data, cpuData);
    if (name == CalcStickyDipoleForceKernel::Name())
        return new CpuCalcStickyDipoleForceKernel(name, platform, data, cpuData);
    throw OpenMMException((std::string("Tried to create kernel with illegal kernel name '")+name+"'").c_str());
}
