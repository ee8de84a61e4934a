#ifndef CPU_RIGID_LANGEVIN_KERNEL_FACTORY_H_
#define CPU_RIGID_LANGEVIN_KERNEL_FACTORY_H_

#include "openmm/KernelFactory.h"

namespace RigidLangevinPlugin {

/** Creates the CPU platform's kernels of the plugin. */
class CpuRigidLangevinKernelFactory : public OpenMM::KernelFactory {
public:
    OpenMM::KernelImpl* createKernelImpl(std::string name, const OpenMM::Platform& platform, OpenMM::ContextImpl& context) const;
};

} // namespace RigidLangevinPlugin

#endif /*CPU_RIGID_LANGEVIN_KERNEL_FACTORY_H_*/
