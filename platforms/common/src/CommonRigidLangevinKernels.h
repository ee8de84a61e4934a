#ifndef COMMON_RIGID_LANGEVIN_KERNELS_H_
#define COMMON_RIGID_LANGEVIN_KERNELS_H_

#include "CommonBlobMobility.h"
#include "CommonPseMobility.h"
#include "internal/RigidLangevinStepKernelBase.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include <map>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The implementation of RigidLangevinIntegrator for OpenMM's common compute platforms (OpenCL,
 * CUDA, HIP): one kernel source, compiled at runtime by the platform's ComputeContext.
 *
 * Each step runs one kernel per group of bodies present, a group being one friction class (Scalar,
 * Diagonal, Coupled) and one number of rotations (0, 2, 3): bodies are sorted by group, then type,
 * so that no class pays for another's work and each kernel is compiled for its number of
 * coordinates. One work item per body: gather force and torque from OpenMM's fixed-point force
 * buffer, kick, flow, and place the body's particles; then the platform computes virtual sites. The
 * scheme is compiled into the step kernels (one program per scheme, compiled when first used). Each
 * body makes its normal random numbers in the step kernel from a counter-based generator
 * (rigidBodyRandom.cc) keyed by the seed, with the body, the draw and randomStep as the counter: the
 * generator's state is the seed and randomStep, which the integrator's checkpoint holds.
 *
 * With hydrodynamic interactions (and friction) a step couples all bodies at once: the bodies'
 * states and the forces are read back, and the step is the host's in double precision
 * (RigidLangevinStepKernelBase::takeCoupledStep), with the products of the blobs' mobility of
 * its Krylov solves on the device (CommonBlobMobility) and its normal numbers from the same
 * counter-based generator, keyed by the seed and randomStep.
 *
 * Body states are kept in the platform's "mixed" precision (double in mixed and double precision);
 * rotations are made orthonormal whenever read (rigidBodyAtoms.cc), so that rounding cannot
 * accumulate in single precision. When OpenMM reorders atoms (for its neighbour lists), a reorder
 * listener updates where each body's particles are stored and their periodic cell offsets.
 */
class CommonIntegrateRigidLangevinStepKernel : public RigidLangevinStepKernelBase {
public:
    CommonIntegrateRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc);
    void initialize(const OpenMM::System& system, const RigidBodyIntegrator& integrator);
protected:
    void initializeBodies(OpenMM::ContextImpl& context, const RigidBodyModel& model);
    void uploadBodyStates(OpenMM::ContextImpl& context, const std::vector<BodyState>& states);
    void downloadBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states);
    void uploadCoefficients(OpenMM::ContextImpl& context, const std::vector<TypeStepCoefficients>& coefficients);
    void takeStep(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion);
    void computeBodyKineticEnergies(OpenMM::ContextImpl& context, double timeShift, double& translational, double& rotational, OpenMM::Vec3& momentum);
    void createRandomCheckpoint(std::ostream& stream);
    void loadRandomCheckpoint(std::istream& stream);
    /** As on the CPU. On an H200 (benchmarks/platforms/results/gpu_h200/hydrodynamic_interactions.csv)
     *  the crossover depends on the bodies' shapes: dense is faster at 120 blobs of four-blob bodies,
     *  Krylov at 50 single spheres; 100 is within 1.5 times of the faster at every size measured. */
    int getDefaultKrylovMinBlobs() const {
        return 100;
    }
    /** From the step kernels' counter-based generator, keyed by the seed and randomStep (one a step). */
    std::function<double ()> hostNormals();
    /** The device's products of the blobs' mobility (CommonBlobMobility). */
    BlobMobility& blobMobility();
    /** On the context's host threads (ComputeContext::getThreadPool()): the host's share of the coupled step, the PSE's preparation. */
    void parallelFor(int count, const std::function<void (int, int)>& task);
    /** The spectral solver's products on the device (CommonPseMobility). */
    SpectralBlobMobility* createSpectralMobility(const std::string& integratorName, const KrylovSolvers::ParallelFor& parallel);
    void finishHostStep(OpenMM::ContextImpl& context, double h);
private:
    std::unique_ptr<CommonBlobMobility> deviceMobility;
    class AtomOrderListener;
    /** Find where each body particle is stored now, and its periodic cell offset. */
    void updateAtomSlots();
    void setKernelArguments();
    void setStepArguments(std::vector<OpenMM::ComputeKernel>& kernels);
    /** The step kernels of a scheme (one per step group), compiled and given their arguments on first use. */
    std::vector<OpenMM::ComputeKernel>& stepKernelsFor(RigidLangevinIntegrator::Scheme scheme);
    void placeAtoms();
    void uploadTypeParameters();
    /** (Re)size the arrays stored in the platform's mixed precision. */
    template <class Mixed, class Mixed4>
    void initializeMixedArrays(int numTypes, int numTypeCoords);
    template <class Mixed, class Mixed4>
    void uploadStates(const std::vector<BodyState>& states);
    template <class Mixed, class Mixed4>
    void downloadStates(std::vector<BodyState>& states);
    /** Normal random numbers, in float4s, one body of a step group takes per step. */
    static int randomFloat4PerBody(int group, RigidLangevinIntegrator::Scheme scheme, bool frictionless);
    OpenMM::ComputeContext& cc;
    /** Set the periodic box vectors (and whether there is a box) as arguments of the kernels that take them. */
    void setBoxArguments();
    bool mixedIsDouble, hasSetArguments, periodic;
    int numBodies, numEntries, numReductionGroups;
    unsigned int randomSeed;             // the random numbers' key
    unsigned long long randomStep;       // the counter's step: steps taken since the Context was made (or the checkpoint was)
    std::vector<int> groupStart;         // kernel body range of each step group (RigidBodyKernelLayout)
    std::vector<int> bodyOrder;          // kernel body index -> model body index
    std::vector<int> entryParticle;      // body particle entry -> System particle index
    std::vector<double> hostTypeParams;  // TypeStride values per type, in double precision
    std::vector<OpenMM::mm_int4> hostTypeInfo;  // per type: first index in typeCoords, numRotations, halfSteps, friction class
    OpenMM::ComputeArray bodyPosition, bodyVelocity, bodyAngularMomentum, bodyRotation, bodyType, bodyAtomStart;
    OpenMM::ComputeArray atomSlot, atomCellOffset, typeCoords;
    OpenMM::ComputeArray bodyImage;      // int4 per body: the periodic boxes its stored centre is short of the true one
    OpenMM::ComputeArray typeParams, typeInfo, centerOfMassVelocity, kineticEnergies;
    std::map<int, std::vector<OpenMM::ComputeKernel> > stepKernels;  // per scheme: one per step group
    OpenMM::ComputeKernel placeKernel, centerOfMassKernel, kineticEnergyKernel;
};

} // namespace RigidLangevinPlugin

#endif /*COMMON_RIGID_LANGEVIN_KERNELS_H_*/
