#ifndef REFERENCE_RIGID_LANGEVIN_KERNEL_FACTORY_H_
#define REFERENCE_RIGID_LANGEVIN_KERNEL_FACTORY_H_

#include "openmm/KernelFactory.h"

namespace RigidLangevinPlugin {

/** Creates the Reference platform's kernels of the plugin. */
class ReferenceRigidLangevinKernelFactory : public OpenMM::KernelFactory {
public:
    OpenMM::KernelImpl* createKernelImpl(std::string name, const OpenMM::Platform& platform, OpenMM::ContextImpl& context) const;
};

} // namespace RigidLangevinPlugin

#endif /*REFERENCE_RIGID_LANGEVIN_KERNEL_FACTORY_H_*/
