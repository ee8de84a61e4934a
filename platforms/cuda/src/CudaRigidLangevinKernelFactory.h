#ifndef CUDA_RIGID_LANGEVIN_KERNEL_FACTORY_H_
#define CUDA_RIGID_LANGEVIN_KERNEL_FACTORY_H_

#include "openmm/KernelFactory.h"

namespace RigidLangevinPlugin {

/** Creates the CUDA platform's kernels of the plugin: the common kernels on a CudaContext. */
class CudaRigidLangevinKernelFactory : public OpenMM::KernelFactory {
public:
    OpenMM::KernelImpl* createKernelImpl(std::string name, const OpenMM::Platform& platform, OpenMM::ContextImpl& context) const;
};

} // namespace RigidLangevinPlugin

#endif /*CUDA_RIGID_LANGEVIN_KERNEL_FACTORY_H_*/
