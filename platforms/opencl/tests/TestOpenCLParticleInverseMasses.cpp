// tests/TestParticleInverseMasses.h on the OpenCL platform: velm read from OpenMM's OpenCL context.
#include "OpenCLTests.h"
#include "TestParticleInverseMasses.h"
#include "openmm/opencl/OpenCLContext.h"
#include "openmm/opencl/OpenCLPlatform.h"

std::vector<double> inverseMassesOnDevice(ContextImpl& context) {
    return inverseMassesIn(*static_cast<OpenCLPlatform::PlatformData*>(context.getPlatformData())->contexts[0]);
}
