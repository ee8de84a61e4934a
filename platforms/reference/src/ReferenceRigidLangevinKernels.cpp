#include "ReferenceRigidLangevinKernels.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;

// The host step's one instantiation for the Reference platform (see ReferenceRigidLangevinKernels.h).
template class RigidLangevinPlugin::HostRigidLangevinStepKernel<GaussianRandom>;

void ReferenceIntegrateRigidLangevinStepKernel::initialize(const System& system, const RigidBodyIntegrator& integrator) {
    RigidLangevinStepKernelBase::initialize(system, integrator);
    std::vector<std::unique_ptr<RandomStream> > streams;
    streams.emplace_back(new RandomStream(integrator.getRandomNumberSeed()));
    setChunks(model->getNumBodies(), std::move(streams));
}

void ReferenceIntegrateRigidLangevinStepKernel::createRandomCheckpoint(std::ostream& stream) {
    random[0]->random.createCheckpoint(stream);
}

void ReferenceIntegrateRigidLangevinStepKernel::loadRandomCheckpoint(std::istream& stream) {
    random[0]->random.loadCheckpoint(stream);
}
