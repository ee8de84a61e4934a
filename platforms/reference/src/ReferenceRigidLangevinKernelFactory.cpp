#include "ReferenceRigidLangevinKernelFactory.h"
#include "ReferenceRigidLangevinKernels.h"
#include "ReferencePlatform.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    // The CPU platform derives from the Reference platform and shares its data, so it uses these
    // kernels too.
    for (int i = 0; i < Platform::getNumPlatforms(); i++) {
        Platform& platform = Platform::getPlatform(i);
        if (dynamic_cast<ReferencePlatform*>(&platform) != NULL)
            platform.registerKernelFactory(IntegrateRigidLangevinStepKernel::Name(), new ReferenceRigidLangevinKernelFactory());
    }
}

extern "C" OPENMM_EXPORT void registerRigidLangevinReferenceKernelFactories() {
    registerKernelFactories();
}

KernelImpl* ReferenceRigidLangevinKernelFactory::createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const {
    ReferencePlatform::PlatformData& data = *static_cast<ReferencePlatform::PlatformData*>(context.getPlatformData());
    if (name == IntegrateRigidLangevinStepKernel::Name())
        return new ReferenceIntegrateRigidLangevinStepKernel(name, platform, data);
    throw OpenMMException((std::string("Tried to create kernel with illegal kernel name '")+name+"'").c_str());
}
