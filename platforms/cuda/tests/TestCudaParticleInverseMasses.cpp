// tests/TestParticleInverseMasses.h on the CUDA platform: velm read from OpenMM's CUDA context.
#include "CudaTests.h"
#include "TestParticleInverseMasses.h"
#include "openmm/cuda/CudaContext.h"
#include "openmm/cuda/CudaPlatform.h"

std::vector<double> inverseMassesOnDevice(ContextImpl& context) {
    return inverseMassesIn(*static_cast<CudaPlatform::PlatformData*>(context.getPlatformData())->contexts[0]);
}
