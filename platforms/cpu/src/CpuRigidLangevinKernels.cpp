#include "CpuRigidLangevinKernels.h"
#include "internal/BodyDynamics.h"
#include "ReferenceVirtualSites.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/OSRngSeed.h"
#include <algorithm>
#include <cstdint>
#include <istream>
#include <ostream>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

namespace {

/**
 * The seed of one chunk's random stream: a 32-bit mix of the integrator's seed and the chunk
 * index (MurmurHash3's finalizer), so that neighbouring chunks start far apart.
 */
uint32_t chunkSeed(uint32_t seed, int chunk) {
    uint32_t h = seed ^ (0x9e3779b9u*(uint32_t) (chunk+1));
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

} // namespace

CpuIntegrateRigidLangevinStepKernel::CpuIntegrateRigidLangevinStepKernel(std::string name, const Platform& platform,
        ReferencePlatform::PlatformData& data, CpuPlatform::PlatformData& cpuData) :
        RigidLangevinStepKernelBase(name, platform), data(data), threads(cpuData.threads) {
}

void CpuIntegrateRigidLangevinStepKernel::initialize(const System& system, const RigidLangevinIntegrator& integrator) {
    RigidLangevinStepKernelBase::initialize(system, integrator);
    int numBodies = model->getNumBodies();
    int numChunks = std::max(1, std::min(numBodies, (int) MaxChunks));
    chunkStart.resize(numChunks+1);
    for (int c = 0; c <= numChunks; c++)
        chunkStart[c] = (int) ((long long) c*numBodies/numChunks);
    // A seed of 0 means a unique one: pick it once, then derive every chunk's from it.
    uint32_t seed = (integrator.getRandomNumberSeed() == 0 ? (uint32_t) osrngseed() : (uint32_t) integrator.getRandomNumberSeed());
    random.clear();
    for (int c = 0; c < numChunks; c++)
        random.emplace_back(new RandomStream(chunkSeed(seed, c)));
}

void CpuIntegrateRigidLangevinStepKernel::forEachChunk(const std::function<void (int, int, int)>& task) {
    int numChunks = chunkStart.size()-1;
    if (chunkStart[numChunks] < MinBodiesForThreads || threads.getNumThreads() == 1) {
        // Waking the threads would cost more than the work; the chunks (and so the results) are the same.
        for (int c = 0; c < numChunks; c++)
            task(c, chunkStart[c], chunkStart[c+1]);
        return;
    }
    threads.execute([&] (ThreadPool& pool, int threadIndex) {
        for (int c = threadIndex; c < numChunks; c += pool.getNumThreads())
            task(c, chunkStart[c], chunkStart[c+1]);
    });
    threads.waitForThreads();
}

void CpuIntegrateRigidLangevinStepKernel::initializeBodies(ContextImpl& context, const RigidBodyModel& model) {
    bodies.resize(model.getNumBodies());
}

void CpuIntegrateRigidLangevinStepKernel::placeParticles(int body, const BodyState& s) {
    const BodyType& type = model->getType(model->getBodyType(body));
    const vector<int>& particles = model->getBodyParticles(body);
    vector<Vec3>& positions = *data.positions;
    vector<Vec3>& velocities = *data.velocities;
    Vec3 omega;  // body frame
    for (int k = 0; k < 3; k++)
        omega[k] = (type.rotates(k) ? s.angularMomentum[k]/type.inertia[k] : 0.0);
    for (int i = 0; i < (int) particles.size(); i++) {
        const Vec3& c = type.coords[i];
        positions[particles[i]] = s.position+BodyDynamics::toLab(s.rotation, c);
        velocities[particles[i]] = s.velocity+BodyDynamics::toLab(s.rotation, omega.cross(c));
    }
}

void CpuIntegrateRigidLangevinStepKernel::uploadBodyStates(ContextImpl& context, const vector<BodyState>& states) {
    forEachChunk([&] (int chunk, int begin, int end) {
        for (int b = begin; b < end; b++) {
            bodies.store(b, states[b]);
            placeParticles(b, states[b]);
        }
    });
}

void CpuIntegrateRigidLangevinStepKernel::downloadBodyStates(ContextImpl& context, vector<BodyState>& states) {
    states.resize(bodies.size());
    for (int b = 0; b < bodies.size(); b++)
        states[b] = bodies.load(b);
}

void CpuIntegrateRigidLangevinStepKernel::uploadCoefficients(ContextImpl& context, const vector<TypeStepCoefficients>& c) {
    // The base class keeps them in `coefficients`; they are read in place.
}

void CpuIntegrateRigidLangevinStepKernel::computeBodyForce(int body, const BodyState& s, Vec3& force, Vec3& torque) const {
    // The same sums, in the same order, as the Reference kernel's.
    const BodyType& type = model->getType(model->getBodyType(body));
    const vector<int>& particles = model->getBodyParticles(body);
    const vector<Vec3>& f = *data.forces;
    force = Vec3();
    torque = Vec3();
    for (int i = 0; i < (int) particles.size(); i++) {
        if (type.isVirtualSite[i])
            continue;  // OpenMM has already added its force to its parents
        const Vec3& fi = f[particles[i]];
        force += fi;
        if (type.numRotations > 0)
            torque += type.coords[i].cross(BodyDynamics::toBody(s.rotation, fi));
    }
}

Vec3 CpuIntegrateRigidLangevinStepKernel::computeMomentum() {
    int numChunks = chunkStart.size()-1;
    vector<Vec3> chunkMomentum(numChunks);
    forEachChunk([&] (int chunk, int begin, int end) {
        Vec3 sum;
        for (int b = begin; b < end; b++)
            sum += bodies.velocity[b]*model->getType(model->getBodyType(b)).mass;
        chunkMomentum[chunk] = sum;
    });
    Vec3 momentum;
    for (const Vec3& p : chunkMomentum)
        momentum += p;
    return momentum;
}

void CpuIntegrateRigidLangevinStepKernel::takeStep(ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion) {
    const double h = integrator.getStepSize();
    Vec3 centerOfMassVelocity;
    if (removeMotion)
        centerOfMassVelocity = computeMomentum()/model->getTotalMass();
    const RigidLangevinIntegrator::Scheme scheme = integrator.getScheme();
    const bool frictionless = (integrator.getViscosity() == 0);
    // One pass per body: forces, kick, flow and placing its particles, while the body is in cache.
    forEachChunk([&] (int chunk, int begin, int end) {
        ZigguratGaussianRandom& rng = random[chunk]->random;
        for (int b = begin; b < end; b++) {
            int typeIndex = model->getBodyType(b);
            const BodyType& type = model->getType(typeIndex);
            const TypeStepCoefficients& c = coefficients[typeIndex];
            BodyState s = bodies.load(b);
            if (removeMotion)
                s.velocity -= centerOfMassVelocity;
            Vec3 force, torque;
            computeBodyForce(b, s, force, torque);
            if (scheme == RigidLangevinIntegrator::Original)
                BodyDynamics::originalStep(s, type, c, force, torque, h, rng);
            else {
                // Velocities are kept between flow and kick, so the two half kicks of consecutive
                // steps are one full kick (see the Reference kernel).
                BodyDynamics::kick(s, type, force, torque, h);
                if (scheme == RigidLangevinIntegrator::ExactFlow) {
                    if (frictionless)
                        BodyDynamics::drift(s, type, h);
                    else
                        BodyDynamics::exactFlow(s, type, c, h, rng);
                }
                else {
                    BodyDynamics::drift(s, type, 0.5*h);
                    if (!frictionless)
                        BodyDynamics::ornsteinUhlenbeck(s, type, c, rng);
                    BodyDynamics::drift(s, type, 0.5*h);
                }
            }
            bodies.store(b, s);
            placeParticles(b, s);
        }
    });
    data.virtualSites->computePositions(context.getSystem(), *data.positions, data.periodicBoxVectors);
    data.time += h;
    data.stepCount++;
}

void CpuIntegrateRigidLangevinStepKernel::computeBodyKineticEnergies(ContextImpl& context, double timeShift,
        double& translational, double& rotational, Vec3& momentum) {
    int numChunks = chunkStart.size()-1;
    vector<double> chunkTranslational(numChunks), chunkRotational(numChunks);
    vector<Vec3> chunkMomentum(numChunks);
    forEachChunk([&] (int chunk, int begin, int end) {
        double kt = 0, kr = 0;
        Vec3 p;
        for (int b = begin; b < end; b++) {
            const BodyType& type = model->getType(model->getBodyType(b));
            BodyState s = bodies.load(b);
            if (timeShift != 0) {
                Vec3 force, torque;
                computeBodyForce(b, s, force, torque);
                BodyDynamics::kick(s, type, force, torque, timeShift);
            }
            kt += 0.5*type.mass*s.velocity.dot(s.velocity);
            p += s.velocity*type.mass;
            for (int k = 0; k < 3; k++)
                if (type.rotates(k))
                    kr += 0.5*s.angularMomentum[k]*s.angularMomentum[k]/type.inertia[k];
        }
        chunkTranslational[chunk] = kt;
        chunkRotational[chunk] = kr;
        chunkMomentum[chunk] = p;
    });
    translational = rotational = 0;
    momentum = Vec3();
    for (int c = 0; c < numChunks; c++) {
        translational += chunkTranslational[c];
        rotational += chunkRotational[c];
        momentum += chunkMomentum[c];
    }
}

void CpuIntegrateRigidLangevinStepKernel::createRandomCheckpoint(std::ostream& stream) {
    int numStreams = random.size();
    stream.write((char*) &numStreams, sizeof(int));
    for (auto& r : random)
        r->random.createCheckpoint(stream);
}

void CpuIntegrateRigidLangevinStepKernel::loadRandomCheckpoint(std::istream& stream) {
    int numStreams;
    stream.read((char*) &numStreams, sizeof(int));
    if (!stream || numStreams != (int) random.size())
        throw OpenMMException("RigidLangevinIntegrator: the checkpoint was not written by the CPU platform for this System "
                              "(it has "+std::to_string(numStreams)+" random number streams, this context "+std::to_string(random.size())+")");
    for (auto& r : random)
        r->random.loadCheckpoint(stream);
}
