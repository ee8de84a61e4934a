#ifndef HOST_RIGID_LANGEVIN_STEP_KERNEL_H_
#define HOST_RIGID_LANGEVIN_STEP_KERNEL_H_

#include "HostBodyStates.h"
#include "HostParticleStores.h"
#include "ReferencePlatform.h"
#include "ReferenceVirtualSites.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include "internal/BodyDynamics.h"
#include "internal/RigidLangevinStepKernelBase.h"
#include "internal/TargetClones.h"
#include "openmm/internal/ContextImpl.h"
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The step of RigidLangevinIntegrator on the host, in double precision, written once for the
 * Reference and CPU platforms: scheme dispatch, force and torque gather, particle placement,
 * centre-of-mass motion removal and kinetic energies. Bodies are split into contiguous chunks,
 * each drawing from its own stream of normal random numbers (Random: anything with next()).
 * A platform supplies only how many chunks there are, their random streams (setChunks) and
 * the threads that run them (forEachChunk); every sum runs chunk by chunk in a fixed order, so a
 * trajectory depends on the seed and the forces, not on the number of threads.
 */
template <class Random>
class HostRigidLangevinStepKernel : public RigidLangevinStepKernelBase {
public:
    HostRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data) :
            RigidLangevinStepKernelBase(name, platform), data(data) {
    }
protected:
    /** One chunk's random numbers, alone in its cache lines (threads drawing from neighbouring streams would share them). */
    struct alignas(64) RandomStream {
        template <class Seed>
        explicit RandomStream(Seed seed) : random(seed) {
        }
        Random random;
    };
    /** Split numBodies into one contiguous chunk per random stream, of near-equal sizes. */
    void setChunks(int numBodies, std::vector<std::unique_ptr<RandomStream> >&& streams) {
        random = std::move(streams);
        int numChunks = random.size();
        chunkStart.resize(numChunks+1);
        for (int c = 0; c <= numChunks; c++)
            chunkStart[c] = (int) ((long long) c*numBodies/numChunks);
    }
    /** Run task(chunk, firstBody, endBody) for every chunk and wait. By default, one after another. */
    virtual void forEachChunk(const std::function<void (int, int, int)>& task) {
        for (int c = 0; c+1 < (int) chunkStart.size(); c++)
            task(c, chunkStart[c], chunkStart[c+1]);
    }
    int getNumChunks() const {
        return (int) chunkStart.size()-1;
    }
    /** The first body of a chunk; chunkBegin(getNumChunks()) is the number of bodies. */
    int chunkBegin(int chunk) const {
        return chunkStart[chunk];
    }
    void initializeBodies(OpenMM::ContextImpl& /*context*/, const RigidBodyModel& model) {
        bodies.resize(model.getNumBodies());
        particleStores = hostParticleStores(model);
    }
    void uploadBodyStates(OpenMM::ContextImpl& /*context*/, const std::vector<BodyState>& states) {
        forEachChunk([&] (int /*chunk*/, int begin, int end) {
            for (int b = begin; b < end; b++) {
                bodies.store(b, states[b]);
                model->placeBodyParticles(b, states[b], *data.positions, *data.velocities);
            }
        });
    }
    void downloadBodyStates(OpenMM::ContextImpl& /*context*/, std::vector<BodyState>& states) {
        states.resize(bodies.size());
        for (int b = 0; b < bodies.size(); b++)
            states[b] = bodies.load(b);
    }
    void uploadCoefficients(OpenMM::ContextImpl& /*context*/, const std::vector<TypeStepCoefficients>& /*coefficients*/) {
        // The base class keeps them in `coefficients`; they are read in place.
    }
    /** The first chunk's stream: a trajectory does not depend on the number of threads. */
    std::function<double ()> hostNormals() {
        return [this] () { return random[0]->random.next(); };
    }
    /** The host's products of the blobs' mobility, on this platform's threads. */
    BlobMobility& blobMobility() {
        if (!hostMobility)
            hostMobility.reset(new HostBlobMobility([this] (int count, const std::function<void (int, int)>& task) { parallelFor(count, task); }));
        return *hostMobility;
    }
    void finishHostStep(OpenMM::ContextImpl& context, double h) {
        // Placing the bodies placed their sites; OpenMM's computePositions, which places every
        // site from its parents (about a tenth of a step of four-site water bodies), is for the others.
        if (model->hasSitesOutsideBodies())
            data.virtualSites->computePositions(context.getSystem(), *data.positions, data.periodicBoxVectors);
        data.time += h;
        data.stepCount++;
    }
    void takeStep(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion) {
        const double h = integrator.getStepSize();
        OpenMM::Vec3 centerOfMassVelocity;
        if (removeMotion)
            centerOfMassVelocity = computeMomentum()/model->getTotalMass();
        const RigidLangevinIntegrator::Scheme scheme = integrator.getScheme();
        const bool frictionless = (integrator.getViscosity() == 0);
        if (interactions && !frictionless)
            advanceCoupledBodies(context, integrator);  // no motion to remove: a CMMotionRemover is refused with friction
        else {
            // One pass per body: forces, kick, flow and placing its particles, while the body is in cache.
            forEachChunk([&] (int chunk, int begin, int end) {
                advanceBodies(begin, end, random[chunk]->random, scheme, h, frictionless, removeMotion, centerOfMassVelocity);
            });
        }
        finishHostStep(context, h);
    }
    void computeBodyKineticEnergies(OpenMM::ContextImpl& /*context*/, double timeShift, double& translational, double& rotational, OpenMM::Vec3& momentum) {
        int numChunks = getNumChunks();
        std::vector<double> chunkTranslational(numChunks), chunkRotational(numChunks);
        std::vector<OpenMM::Vec3> chunkMomentum(numChunks);
        forEachChunk([&] (int chunk, int begin, int end) {
            double kt = 0, kr = 0;
            OpenMM::Vec3 p;
            for (int b = begin; b < end; b++) {
                const BodyType& type = model->getType(model->getBodyType(b));
                BodyState s = bodies.load(b);
                if (timeShift != 0) {
                    OpenMM::Vec3 force, torque;
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
        momentum = OpenMM::Vec3();
        for (int c = 0; c < numChunks; c++) {
            translational += chunkTranslational[c];
            rotational += chunkRotational[c];
            momentum += chunkMomentum[c];
        }
    }
    OpenMM::ReferencePlatform::PlatformData& data;
    std::vector<std::unique_ptr<RandomStream> > random;  // one per chunk
private:
    std::unique_ptr<HostBlobMobility> hostMobility;  // the blobs' mobility for matrix-free steps, on this platform's threads
    /** Advance bodies [begin, end) by one step, drawing from rng (in two builds: RIGIDLANGEVIN_CLONES). */
    RIGIDLANGEVIN_CLONES
    void advanceBodies(int begin, int end, Random& rng, RigidLangevinIntegrator::Scheme scheme, double h, bool frictionless,
                       bool removeMotion, OpenMM::Vec3 centerOfMassVelocity) {
        for (int b = begin; b < end; b++) {
            int typeIndex = model->getBodyType(b);
            const BodyType& type = model->getType(typeIndex);
            const TypeStepCoefficients& c = coefficients[typeIndex];
            const bool point = (type.numRotations == 0);
            BodyState s = (point ? bodies.loadPoint(b) : bodies.load(b));
            if (removeMotion)
                s.velocity -= centerOfMassVelocity;
            OpenMM::Vec3 force, torque;
            computeBodyForce(b, s, force, torque);
            if (scheme == RigidLangevinIntegrator::Original)
                BodyDynamics::originalStep(s, type, c, force, torque, h, rng);
            else {
                // Velocities are kept between flow and kick, so the two half kicks of
                // consecutive steps are one full kick. Without friction both schemes are
                // plain velocity Verlet with free rotation.
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
            if (point)
                bodies.storePoint(b, s);
            else
                bodies.store(b, s);
            model->placeBodyParticles(b, s, *data.positions, *data.velocities, particleStores);
        }
        // Non-temporal stores are weakly ordered: the thread pool's hand-back (release and acquire)
        // does not order them before the force evaluation's reads on another thread; a full fence does.
        if (particleStores == RigidBodyModel::ParticleStores::Streaming)
            std::atomic_thread_fence(std::memory_order_seq_cst);
    }
    /** Total force (lab frame) and torque (body frame) on a body, from the platform's forces. */
    void computeBodyForce(int body, const BodyState& s, OpenMM::Vec3& force, OpenMM::Vec3& torque) const {
        BodyDynamics::gatherForce(model->getType(model->getBodyType(body)), model->getBodyParticles(body), s, *data.forces, force, torque);
    }
    /** The total momentum of all bodies, summed chunk by chunk in a fixed order. */
    OpenMM::Vec3 computeMomentum() {
        std::vector<OpenMM::Vec3> chunkMomentum(getNumChunks());
        forEachChunk([&] (int chunk, int begin, int end) {
            OpenMM::Vec3 sum;
            for (int b = begin; b < end; b++)
                sum += bodies.velocity[b]*model->getType(model->getBodyType(b)).mass;
            chunkMomentum[chunk] = sum;
        });
        OpenMM::Vec3 momentum;
        for (const OpenMM::Vec3& p : chunkMomentum)
            momentum += p;
        return momentum;
    }
    HostBodyStates bodies;
    std::vector<int> chunkStart;
    RigidBodyModel::ParticleStores particleStores = RigidBodyModel::ParticleStores::Cached;
};

} // namespace RigidLangevinPlugin

#endif /*HOST_RIGID_LANGEVIN_STEP_KERNEL_H_*/
