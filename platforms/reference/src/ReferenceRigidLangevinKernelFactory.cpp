#include "ReferenceRigidLangevinKernelFactory.h"
#include "ReferenceRigidLangevinKernels.h"
#include "ReferencePlatform.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

// Called through both entry points below. A plugin calls no exported function of its own: with
// several plugins loaded, the dynamic linker could bind such a call to another plugin's.
void registerFactories() {
    // On every platform derived from ReferencePlatform, as OpenMM's own plugins register theirs,
    // each kernel the platform does not have already: the CPU platform derives from
    // ReferencePlatform but has its own, threaded integrator (platforms/cpu), which it keeps
    // whichever plugin loads first (the CPU plugin registers its kernels on the CPU platform
    // unconditionally).
    for (int i = 0; i < Platform::getNumPlatforms(); i++) {
        Platform& platform = Platform::getPlatform(i);
        if (dynamic_cast<ReferencePlatform*>(&platform) == NULL)
            continue;
        for (const std::string& kernel : {IntegrateRigidLangevinStepKernel::Name(), CalcStickyDipoleForceKernel::Name()})
            if (!platform.supportsKernels({kernel}))
                platform.registerKernelFactory(kernel, new ReferenceRigidLangevinKernelFactory());
    }
}

} // namespace

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    registerFactories();
}

extern "C" OPENMM_EXPORT void registerRigidLangevinReferenceKernelFactories() {
    registerFactories();
}

KernelImpl* ReferenceRigidLangevinKernelFactory::createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const {
    ReferencePlatform::PlatformData& data = *static_cast<ReferencePlatform::PlatformData*>(context.getPlatformData());
    if (name == IntegrateRigidLangevinStepKernel::Name())
        return new ReferenceIntegrateRigidLangevinStepKernel(name, platform, data);
    if (name == CalcStickyDipoleForceKernel::Name())
        return new ReferenceCalcStickyDipoleForceKernel(name, platform, data);
    throw OpenMMException((std::string("Tried to create kernel with illegal kernel name '")+name+"'").c_str());
}
