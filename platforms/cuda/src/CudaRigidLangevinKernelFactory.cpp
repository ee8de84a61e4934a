#include "CudaRigidLangevinKernelFactory.h"
#include "CommonCalcStickyDipoleForceKernel.h"
#include "CommonRigidLangevinKernels.h"
#include "CudaContext.h"
#include "CudaPlatform.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

// Called through both entry points below (a plugin calls no exported function of its own).
void registerFactories() {
    for (int i = 0; i < Platform::getNumPlatforms(); i++) {
        Platform& platform = Platform::getPlatform(i);
        if (platform.getName() == "CUDA") {
            platform.registerKernelFactory(IntegrateRigidLangevinStepKernel::Name(), new CudaRigidLangevinKernelFactory());
            platform.registerKernelFactory(CalcStickyDipoleForceKernel::Name(), new CudaRigidLangevinKernelFactory());
        }
    }
}

} // namespace

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    registerFactories();
}

extern "C" OPENMM_EXPORT void registerRigidLangevinCUDAKernelFactories() {
    registerFactories();
}

KernelImpl* CudaRigidLangevinKernelFactory::createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const {
    CudaContext& cu = *static_cast<CudaPlatform::PlatformData*>(context.getPlatformData())->contexts[0];
    if (name == IntegrateRigidLangevinStepKernel::Name())
        return new CommonIntegrateRigidLangevinStepKernel(name, platform, cu);
    if (name == CalcStickyDipoleForceKernel::Name())
        return new CommonCalcStickyDipoleForceKernel(name, platform, cu);
    throw OpenMMException((std::string("Tried to create kernel with illegal kernel name '")+name+"'").c_str());
}
