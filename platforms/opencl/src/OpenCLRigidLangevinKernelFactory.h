#ifndef OPENCL_RIGID_LANGEVIN_KERNEL_FACTORY_H_
#define OPENCL_RIGID_LANGEVIN_KERNEL_FACTORY_H_

#include "openmm/KernelFactory.h"

namespace RigidLangevinPlugin {

/** Creates the OpenCL platform's kernels of the plugin: the common kernels on an OpenCLContext. */
class OpenCLRigidLangevinKernelFactory : public OpenMM::KernelFactory {
public:
    OpenMM::KernelImpl* createKernelImpl(std::string name, const OpenMM::Platform& platform, OpenMM::ContextImpl& context) const;
};

} // namespace RigidLangevinPlugin

#endif /*OPENCL_RIGID_LANGEVIN_KERNEL_FACTORY_H_*/
