// tests/TestDeviceBlobMobility.h on the CUDA platform: the product on OpenMM's CUDA context.
#include "CudaTests.h"
#include "TestDeviceBlobMobility.h"
#include "openmm/cuda/CudaContext.h"
#include "openmm/cuda/CudaPlatform.h"

ComputeContext& computeContextOf(ContextImpl& context) {
    return *static_cast<CudaPlatform::PlatformData*>(context.getPlatformData())->contexts[0];
}
