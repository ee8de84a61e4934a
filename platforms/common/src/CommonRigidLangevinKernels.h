#ifndef COMMON_RIGID_LANGEVIN_KERNELS_H_
#define COMMON_RIGID_LANGEVIN_KERNELS_H_

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
 * Body states are kept in the platform's "mixed" precision (double in mixed and double precision);
 * rotations are made orthonormal whenever read (rigidBodyAtoms.cc), so that rounding cannot
 * accumulate in single precision. When OpenMM reorders atoms (for its neighbour lists), a reorder
 * listener updates where each body's particles are stored.
 *
 * In a periodic box every particle of a body has the same cell offset in OpenMM's posCellOffsets,
 * set here (OpenMM's own is per molecule, and bodies need not be molecules to it): particle p of
 * body b is stored at the stored centre + Q^T c_p + shift_b (whole boxes), and OpenMM reads its
 * true position as that minus cell_b, so the step reads one int4 per body rather than one per
 * particle; the boxes the stored centre is short of the true one are shift_b - cell_b. Whenever
 * states are set and whenever OpenMM reorders atoms (which is when it wraps molecules), bodies
 * are recentred and their particles placed again, so that stored positions stay near the box, as
 * OpenMM keeps them: cell_b = -image_b, shift_b = 0. A virtual site outside every body is computed
 * by OpenMM from its parents' stored positions, so bodies holding parents of one such site form a
 * group that shares one cell offset, its first body's (the others keep a shift), and so does the
 * site.
 */
class CommonIntegrateRigidLangevinStepKernel : public RigidLangevinStepKernelBase {
public:
    CommonIntegrateRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc);
    void initialize(const OpenMM::System& system, const RigidLangevinIntegrator& integrator);
protected:
    void initializeBodies(OpenMM::ContextImpl& context, const RigidBodyModel& model);
    void uploadBodyStates(OpenMM::ContextImpl& context, const std::vector<BodyState>& states);
    void downloadBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states);
    void uploadCoefficients(OpenMM::ContextImpl& context, const std::vector<TypeStepCoefficients>& coefficients);
    void takeStep(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion);
    void computeBodyKineticEnergies(OpenMM::ContextImpl& context, double timeShift, double& translational, double& rotational, OpenMM::Vec3& momentum);
    void createRandomCheckpoint(std::ostream& stream);
    void loadRandomCheckpoint(std::istream& stream);
private:
    class AtomOrderListener;
    /** Find where each body particle is stored now; in a periodic box, recentre bodies whose states are set. */
    void atomsReordered();
    /** Find where each body particle is stored now. */
    void updateAtomSlots();
    /** Set bodyCell as every particle's cell offset in OpenMM's posCellOffsets, and the group's for sites outside bodies. */
    void setBodyCells();
    /** Group the bodies that hold parents of one virtual site outside every body (class comment). */
    void linkBodiesThroughSites(const OpenMM::System& system);
    /** Set bodyCell for bodies whose true centres are image boxes beyond their stored ones; returns their shifts. */
    std::vector<OpenMM::mm_int4> recentre(const std::vector<OpenMM::mm_int4>& image);
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
    bool mixedIsDouble, hasSetArguments, periodic, hasStates;
    int numBodies, numEntries, numReductionGroups;
    unsigned int randomSeed;             // the random numbers' key
    unsigned long long randomStep;       // the counter's step: steps taken since the Context was made (or the checkpoint was)
    std::vector<int> groupStart;         // kernel body range of each step group (RigidBodyKernelLayout)
    std::vector<int> bodyOrder;          // kernel body index -> model body index
    std::vector<int> entryParticle;      // body particle entry -> System particle index
    std::vector<int> entrySlot;          // body particle entry -> where OpenMM stores it now (atomSlot's host copy)
    std::vector<double> hostTypeParams;  // TypeStride values per type, in double precision
    std::vector<OpenMM::mm_int4> hostTypeInfo;  // per type: first index in typeCoords, numRotations, halfSteps, friction class
    OpenMM::ComputeArray bodyPosition, bodyVelocity, bodyAngularMomentum, bodyRotation, bodyType, bodyAtomStart;
    std::vector<OpenMM::mm_int4> bodyCell;  // per body: the cell offset OpenMM holds for each of its particles
    std::vector<int> hostAtomStart;      // bodyAtomStart's host copy
    std::vector<int> bodyLeader;         // per body: the first body of its group (linkBodiesThroughSites)
    std::vector<int> siteParticle, siteLeader, siteSlot;  // virtual sites outside bodies whose parents are in one: group, where stored
    OpenMM::ComputeArray atomSlot, typeCoords;
    OpenMM::ComputeArray bodyShift;      // int4 per body: the whole boxes its particles are stored shifted by (class comment)
    OpenMM::ComputeArray typeParams, typeInfo, centerOfMassVelocity, kineticEnergies;
    std::map<int, std::vector<OpenMM::ComputeKernel> > stepKernels;  // per scheme: one per step group
    OpenMM::ComputeKernel placeKernel, centerOfMassKernel, kineticEnergyKernel;
};

} // namespace RigidLangevinPlugin

#endif /*COMMON_RIGID_LANGEVIN_KERNELS_H_*/
