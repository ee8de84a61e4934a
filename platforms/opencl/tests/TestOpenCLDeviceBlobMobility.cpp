// tests/TestDeviceBlobMobility.h on the OpenCL platform: the product on OpenMM's OpenCL context.
#include "OpenCLTests.h"
#include "TestDeviceBlobMobility.h"
#include "openmm/opencl/OpenCLContext.h"
#include "openmm/opencl/OpenCLPlatform.h"

ComputeContext& computeContextOf(ContextImpl& context) {
    return *static_cast<OpenCLPlatform::PlatformData*>(context.getPlatformData())->contexts[0];
}
