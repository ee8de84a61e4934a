#include "OpenCLRigidLangevinKernelFactory.h"
#include "CommonCalcStickyDipoleForceKernel.h"
#include "CommonRigidLangevinKernels.h"
#include "OpenCLContext.h"
#include "OpenCLPlatform.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

// Called through both entry points below (a plugin calls no exported function of its own).
void registerFactories() {
    for (int i = 0; i < Platform::getNumPlatforms(); i++) {
        Platform& platform = Platform::getPlatform(i);
        if (platform.getName() == "OpenCL") {
            platform.registerKernelFactory(IntegrateRigidLangevinStepKernel::Name(), new OpenCLRigidLangevinKernelFactory());
            platform.registerKernelFactory(CalcStickyDipoleForceKernel::Name(), new OpenCLRigidLangevinKernelFactory());
        }
    }
}

} // namespace

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    registerFactories();
}

extern "C" OPENMM_EXPORT void registerRigidLangevinOpenCLKernelFactories() {
    registerFactories();
}

KernelImpl* OpenCLRigidLangevinKernelFactory::createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const {
    OpenCLContext& cl = *static_cast<OpenCLPlatform::PlatformData*>(context.getPlatformData())->contexts[0];
    if (name == IntegrateRigidLangevinStepKernel::Name())
        return new CommonIntegrateRigidLangevinStepKernel(name, platform, cl);
    if (name == CalcStickyDipoleForceKernel::Name())
        return new CommonCalcStickyDipoleForceKernel(name, platform, cl);
    throw OpenMMException((std::string("Tried to create kernel with illegal kernel name '")+name+"'").c_str());
}
