#include "CommonRigidLangevinKernels.h"
#include "CommonArrays.h"
#include <array>
#include <memory>
#include "RigidBodyKernelLayout.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
#include "openmm/common/IntegrationUtilities.h"
#include "openmm/internal/ContextImpl.h"
#include <algorithm>
#include <map>
#include <numeric>
#include <random>

// The device's normal numbers (kernels/rigidBodyRandom.cc, written to compile on the host too), for
// the coupled step taken on the host.
#define DEVICE static inline
typedef unsigned long long mm_ulong;
#include "kernels/rigidBodyRandom.cc"
#undef DEVICE

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::RigidBodyKernelLayout;
using namespace OpenMM;
using std::string;
using std::vector;

namespace {

/** Arguments of the step kernels set at every step (the seed: when a checkpoint is loaded; the others are fixed). */
enum StepArgument {
    StepFirst = 0, StepLast = 1, StepFrictionless = 2, StepSize = 3, StepRemoveMotion = 4,
    StepRandomSeed = 17, StepRandomStep = 18, StepRandomPerBody = 19, StepBox = 22
};

/** The first periodic box vector argument of placeBodyAtoms. */
const int PlaceBox = 16;

/** Whole boxes to subtract from r to bring it into the periodic box of reduced vectors a, b, c (as keepInBox does). */
mm_int4 imageOf(Vec3& r, const Vec3* box) {
    int image[3];
    for (int i = 2; i >= 0; i--) {
        image[i] = (int) std::floor(r[i]/box[i][i]);
        r -= box[i]*image[i];
    }
    return mm_int4(image[0], image[1], image[2], 0);
}

/** Set a kernel argument of the device's "mixed" type. */
void setMixedArg(ComputeKernel& kernel, int index, double value, bool mixedIsDouble) {
    if (mixedIsDouble)
        kernel->setArg(index, value);
    else
        kernel->setArg(index, (float) value);
}

void setMixed4Arg(ComputeKernel& kernel, int index, const Vec3& v, bool mixedIsDouble) {
    if (mixedIsDouble)
        kernel->setArg(index, mm_double4(v[0], v[1], v[2], 0));
    else
        kernel->setArg(index, mm_float4((float) v[0], (float) v[1], (float) v[2], 0));
}

} // namespace

/**
 * Told by the ComputeContext whenever it has reordered atoms (and when it restores a checkpoint),
 * so that bodies find their particles where they are now.
 */
class CommonIntegrateRigidLangevinStepKernel::AtomOrderListener : public ComputeContext::ReorderListener {
public:
    explicit AtomOrderListener(CommonIntegrateRigidLangevinStepKernel& owner) : owner(owner) {
    }
    void execute() {
        owner.updateAtomSlots();
    }
private:
    CommonIntegrateRigidLangevinStepKernel& owner;
};

CommonIntegrateRigidLangevinStepKernel::CommonIntegrateRigidLangevinStepKernel(string name, const Platform& platform, ComputeContext& cc) :
        RigidLangevinStepKernelBase(name, platform), cc(cc), mixedIsDouble(false), hasSetArguments(false), periodic(false), numBodies(0), numEntries(0),
        numReductionGroups(1), randomSeed(0), randomStep(0) {
}

void CommonIntegrateRigidLangevinStepKernel::initialize(const System& system, const RigidBodyIntegrator& integrator) {
    RigidLangevinStepKernelBase::initialize(system, integrator);
    cc.initializeContexts();
    ContextSelector selector(cc);
    mixedIsDouble = (cc.getUseDoublePrecision() || cc.getUseMixedPrecision());
    periodic = system.usesPeriodicBoundaryConditions();
    // The random numbers' key: the seed, or (seed 0, as OpenMM's integrators take it) one of its own.
    randomSeed = (unsigned int) integrator.getRandomNumberSeed();
    if (randomSeed == 0)
        randomSeed = std::random_device()();
    randomStep = 0;
    // The overdamped step runs on the host (BrownianBodyStep); its Context still places, reduces and
    // sums kinetic energies with this program's kernels, compiled here for BAOAB's layout.
    const RigidLangevinIntegrator* inertial = dynamic_cast<const RigidLangevinIntegrator*>(&integrator);
    const RigidLangevinIntegrator::Scheme scheme = (inertial != NULL ? inertial->getScheme() : RigidLangevinIntegrator::BAOAB);
    ComputeProgram program = cc.compileProgram(RigidBodyKernelLayout::source(),
            RigidBodyKernelLayout::defines(cc.getPaddedNumAtoms(), mixedIsDouble, scheme));
    vector<ComputeKernel>& kernels = stepKernels[scheme];
    for (int group = 0; group < NumStepGroups; group++)
        kernels.push_back(program->createKernel(stepKernelName(group)));
    placeKernel = program->createKernel("placeBodyAtoms");
    centerOfMassKernel = program->createKernel("computeCenterOfMassVelocity");
    kineticEnergyKernel = program->createKernel("computeBodyKineticEnergies");
    cc.addReorderListener(new AtomOrderListener(*this));
}

void CommonIntegrateRigidLangevinStepKernel::initializeBodies(ContextImpl& /*context*/, const RigidBodyModel& model) {
    ContextSelector selector(cc);
    numBodies = model.getNumBodies();

    // Kernel order: by step group, then type, so each group is one range and one kernel.
    bodyOrder.resize(numBodies);
    std::iota(bodyOrder.begin(), bodyOrder.end(), 0);
    auto group = [&] (int body) {
        const BodyType& type = model.getType(model.getBodyType(body));
        return stepGroup(type.frictionClass, type.numRotations);
    };
    std::stable_sort(bodyOrder.begin(), bodyOrder.end(), [&] (int a, int b) {
        return std::make_pair(group(a), model.getBodyType(a)) < std::make_pair(group(b), model.getBodyType(b));
    });
    groupStart.assign(NumStepGroups+1, 0);
    for (int body : bodyOrder)
        groupStart[group(body)+1]++;
    for (int g = 1; g <= NumStepGroups; g++)
        groupStart[g] += groupStart[g-1];

    // Body particles, contiguous per body in kernel order.
    vector<int> types(numBodies), atomStart(numBodies+1);
    entryParticle.clear();
    for (int k = 0; k < numBodies; k++) {
        int body = bodyOrder[k];
        types[k] = model.getBodyType(body);
        atomStart[k] = entryParticle.size();
        for (int particle : model.getBodyParticles(body))
            entryParticle.push_back(particle);
    }
    numEntries = entryParticle.size();

    // Body-frame coordinates once per type (a type's bodies share them, and their masses), the
    // type's first at typeInfo[type].x. w: the particle's inverse mass exactly as OpenMM puts it in
    // velm.w (1/m, 0 if massless), which the step writes there without reading velm; -1 marks a
    // virtual site, whose force OpenMM has already handed to its parents and must not count again
    // (its inverse mass is 0: OpenMM's sites are massless).
    vector<mm_double4> coords;
    vector<int> coordStart(model.getNumTypes());
    for (int t = 0; t < model.getNumTypes(); t++) {
        const BodyType& type = model.getType(t);
        coordStart[t] = coords.size();
        for (int i = 0; i < (int) type.coords.size(); i++) {
            double w = (type.isVirtualSite[i] ? -1.0 : type.masses[i] == 0 ? 0.0 : 1.0/type.masses[i]);
            coords.push_back(mm_double4(type.coords[i][0], type.coords[i][1], type.coords[i][2], w));
        }
    }
    atomStart[numBodies] = numEntries;
    numReductionGroups = std::max(1, std::min(cc.getNumThreadBlocks(), (numBodies+ReductionGroupSize-1)/ReductionGroupSize));

    if (mixedIsDouble)
        initializeMixedArrays<double, mm_double4>(model.getNumTypes(), coords.size());
    else
        initializeMixedArrays<float, mm_float4>(model.getNumTypes(), coords.size());
    fitArray(cc, bodyType, numBodies, sizeof(int), "rigidBodyType", ArrayFit::Exact);
    fitArray(cc, bodyAtomStart, numBodies+1, sizeof(int), "rigidBodyAtomStart", ArrayFit::Exact);
    fitArray(cc, atomSlot, numEntries, sizeof(int), "rigidBodyAtomSlot", ArrayFit::Exact);
    fitArray(cc, atomCellOffset, numEntries, sizeof(mm_int4), "rigidBodyAtomCellOffset", ArrayFit::Exact);
    fitArray(cc, bodyImage, numBodies, sizeof(mm_int4), "rigidBodyImage", ArrayFit::Exact);
    fitArray(cc, typeInfo, model.getNumTypes(), sizeof(mm_int4), "rigidBodyTypeInfo", ArrayFit::Exact);
    if (numBodies > 0) {
        bodyType.upload(types);
        bodyAtomStart.upload(atomStart);
    }
    if (!coords.empty())
        typeCoords.upload(coords, true);

    // Mass properties now (placing particles and kinetic energies need them); step coefficients
    // arrive with uploadCoefficients().
    hostTypeParams.assign(TypeStride*std::max(1, model.getNumTypes()), 0.0);
    hostTypeInfo.assign(std::max(1, model.getNumTypes()), mm_int4(0, 0, 0, 0));
    for (int t = 0; t < model.getNumTypes(); t++) {
        const BodyType& type = model.getType(t);
        double* p = &hostTypeParams[TypeStride*t];
        p[MassAndInertia] = type.mass;
        for (int k = 0; k < 3; k++)
            p[MassAndInertia+1+k] = type.inertia[k];
        hostTypeInfo[t] = mm_int4(coordStart[t], type.numRotations, 0, (int) type.frictionClass);
    }
    uploadTypeParameters();
    updateAtomSlots();
    setKernelArguments();
}

void CommonIntegrateRigidLangevinStepKernel::uploadTypeParameters() {
    typeParams.upload(hostTypeParams, true);
    typeInfo.upload(hostTypeInfo);
}

void CommonIntegrateRigidLangevinStepKernel::updateAtomSlots() {
    if (entryParticle.empty())
        return;
    ContextSelector selector(cc);
    const vector<int>& order = cc.getAtomIndex();
    vector<int> slotOfParticle(order.size());
    for (int slot = 0; slot < (int) order.size(); slot++)
        slotOfParticle[order[slot]] = slot;
    const vector<mm_int4>& cellOffsets = cc.getPosCellOffsets();
    vector<int> slots(numEntries);
    vector<mm_int4> cells(numEntries);
    for (int e = 0; e < numEntries; e++) {
        slots[e] = slotOfParticle[entryParticle[e]];
        cells[e] = cellOffsets[slots[e]];
    }
    atomSlot.upload(slots);
    atomCellOffset.upload(cells);
}

void CommonIntegrateRigidLangevinStepKernel::setKernelArguments() {
    if (hasSetArguments)
        return;
    hasSetArguments = true;
    for (auto& scheme : stepKernels)
        setStepArguments(scheme.second);
    placeKernel->addArg(numBodies);
    placeKernel->addArg(bodyPosition);
    placeKernel->addArg(bodyVelocity);
    placeKernel->addArg(bodyAngularMomentum);
    placeKernel->addArg(bodyRotation);
    placeKernel->addArg(bodyType);
    placeKernel->addArg(typeParams);
    placeKernel->addArg(typeInfo);
    placeKernel->addArg(bodyImage);
    placeKernel->addArg(bodyAtomStart);
    placeKernel->addArg(atomSlot);
    placeKernel->addArg(typeCoords);
    placeKernel->addArg(atomCellOffset);
    placeKernel->addArg(cc.getPosq());
    // Written only in mixed precision; posq stands in for it otherwise.
    placeKernel->addArg(cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq());
    placeKernel->addArg(cc.getVelm());
    for (int i = 0; i < 3; i++)
        placeKernel->addArg();  // periodic box vectors
    centerOfMassKernel->addArg(numBodies);
    centerOfMassKernel->addArg();  // inverse total mass
    centerOfMassKernel->addArg(bodyVelocity);
    centerOfMassKernel->addArg(bodyType);
    centerOfMassKernel->addArg(typeParams);
    centerOfMassKernel->addArg(centerOfMassVelocity);
    kineticEnergyKernel->addArg(numBodies);
    kineticEnergyKernel->addArg();  // time shift
    kineticEnergyKernel->addArg(bodyVelocity);
    kineticEnergyKernel->addArg(bodyAngularMomentum);
    kineticEnergyKernel->addArg(bodyRotation);
    kineticEnergyKernel->addArg(bodyType);
    kineticEnergyKernel->addArg(bodyAtomStart);
    kineticEnergyKernel->addArg(atomSlot);
    kineticEnergyKernel->addArg(typeCoords);
    kineticEnergyKernel->addArg(cc.getLongForceBuffer());
    kineticEnergyKernel->addArg(typeParams);
    kineticEnergyKernel->addArg(typeInfo);
    kineticEnergyKernel->addArg(kineticEnergies);
}

void CommonIntegrateRigidLangevinStepKernel::setStepArguments(vector<ComputeKernel>& kernels) {
    for (ComputeKernel& kernel : kernels) {
        for (int i = 0; i < 5; i++)
            kernel->addArg();
        kernel->addArg(bodyPosition);
        kernel->addArg(bodyVelocity);
        kernel->addArg(bodyAngularMomentum);
        kernel->addArg(bodyRotation);
        kernel->addArg(bodyType);
        kernel->addArg(bodyAtomStart);
        kernel->addArg(atomSlot);
        kernel->addArg(typeCoords);
        kernel->addArg(atomCellOffset);
        kernel->addArg(cc.getLongForceBuffer());
        kernel->addArg(typeParams);
        kernel->addArg(typeInfo);
        kernel->addArg(randomSeed);
        kernel->addArg();  // randomStep
        kernel->addArg();  // random numbers per body
        kernel->addArg(centerOfMassVelocity);
        kernel->addArg(periodic ? 1 : 0);
        for (int i = 0; i < 3; i++)
            kernel->addArg();  // periodic box vectors
        kernel->addArg(bodyImage);
        kernel->addArg(cc.getPosq());
        kernel->addArg(cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq());
        kernel->addArg(cc.getVelm());
    }
}

vector<ComputeKernel>& CommonIntegrateRigidLangevinStepKernel::stepKernelsFor(RigidLangevinIntegrator::Scheme scheme) {
    vector<ComputeKernel>& kernels = stepKernels[scheme];
    if (kernels.empty()) {
        ComputeProgram program = cc.compileProgram(RigidBodyKernelLayout::source(),
                RigidBodyKernelLayout::defines(cc.getPaddedNumAtoms(), mixedIsDouble, scheme));
        for (int group = 0; group < NumStepGroups; group++)
            kernels.push_back(program->createKernel(stepKernelName(group)));
        if (hasSetArguments) {
            setStepArguments(kernels);
            setBoxArguments();
        }
    }
    return kernels;
}

void CommonIntegrateRigidLangevinStepKernel::setBoxArguments() {
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    for (int i = 0; i < 3; i++) {
        setMixed4Arg(placeKernel, PlaceBox+i, box[i], mixedIsDouble);
        for (auto& scheme : stepKernels)
            for (ComputeKernel& kernel : scheme.second)
                setMixed4Arg(kernel, StepBox+i, box[i], mixedIsDouble);
    }
}

void CommonIntegrateRigidLangevinStepKernel::placeAtoms() {
    if (numEntries == 0)
        return;
    placeKernel->execute(numBodies);
}

template <class Mixed, class Mixed4>
void CommonIntegrateRigidLangevinStepKernel::initializeMixedArrays(int numTypes, int numTypeCoords) {
    fitArray(cc, bodyPosition, numBodies, sizeof(Mixed4), "rigidBodyPosition", ArrayFit::Exact);
    fitArray(cc, bodyVelocity, numBodies, sizeof(Mixed4), "rigidBodyVelocity", ArrayFit::Exact);
    fitArray(cc, bodyAngularMomentum, numBodies, sizeof(Mixed4), "rigidBodyAngularMomentum", ArrayFit::Exact);
    fitArray(cc, bodyRotation, numBodies, sizeof(Mixed4), "rigidBodyRotation", ArrayFit::Exact);
    fitArray(cc, typeCoords, numTypeCoords, sizeof(Mixed4), "rigidBodyTypeCoords", ArrayFit::Exact);
    fitArray(cc, typeParams, TypeStride*std::max(1, numTypes), sizeof(Mixed), "rigidBodyTypeParams", ArrayFit::Exact);
    fitArray(cc, centerOfMassVelocity, 1, sizeof(Mixed4), "rigidBodyCenterOfMassVelocity", ArrayFit::Exact);
    fitArray(cc, kineticEnergies, 2*numReductionGroups, sizeof(Mixed4), "rigidBodyKineticEnergies", ArrayFit::Exact);
}

template <class Mixed, class Mixed4>
void CommonIntegrateRigidLangevinStepKernel::uploadStates(const vector<BodyState>& states) {
    vector<Mixed4> position(numBodies), velocity(numBodies), angularMomentum(numBodies), rotation(numBodies);
    vector<mm_int4> image(numBodies, mm_int4(0, 0, 0, 0));
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    for (int k = 0; k < numBodies; k++) {
        const BodyState& s = states[bodyOrder[k]];
        // In the box, in double precision, before rounding to the device's.
        Vec3 r = s.position;
        if (periodic)
            image[k] = imageOf(r, box);
        position[k] = Mixed4((Mixed) r[0], (Mixed) r[1], (Mixed) r[2], 0);
        // The rotation's first two rows, packed as the kernels keep them (rigidBodyAtoms.cc).
        velocity[k] = Mixed4((Mixed) s.velocity[0], (Mixed) s.velocity[1], (Mixed) s.velocity[2], (Mixed) s.rotation[1][1]);
        angularMomentum[k] = Mixed4((Mixed) s.angularMomentum[0], (Mixed) s.angularMomentum[1], (Mixed) s.angularMomentum[2],
                                    (Mixed) s.rotation[1][2]);
        rotation[k] = Mixed4((Mixed) s.rotation[0][0], (Mixed) s.rotation[0][1], (Mixed) s.rotation[0][2], (Mixed) s.rotation[1][0]);
    }
    bodyPosition.upload(position);
    bodyImage.upload(image);
    bodyVelocity.upload(velocity);
    bodyAngularMomentum.upload(angularMomentum);
    bodyRotation.upload(rotation);
}

template <class Mixed, class Mixed4>
void CommonIntegrateRigidLangevinStepKernel::downloadStates(vector<BodyState>& states) {
    vector<Mixed4> position, velocity, angularMomentum, rotation;
    bodyPosition.download(position);
    bodyVelocity.download(velocity);
    bodyAngularMomentum.download(angularMomentum);
    bodyRotation.download(rotation);
    vector<mm_int4> image;
    bodyImage.download(image);
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    states.resize(numBodies);
    for (int k = 0; k < numBodies; k++) {
        BodyState& s = states[bodyOrder[k]];
        s.position = Vec3(position[k].x, position[k].y, position[k].z)+box[0]*image[k].x+box[1]*image[k].y+box[2]*image[k].z;
        s.velocity = Vec3(velocity[k].x, velocity[k].y, velocity[k].z);
        s.angularMomentum = Vec3(angularMomentum[k].x, angularMomentum[k].y, angularMomentum[k].z);
        // The first two rows as the kernels keep them; the third is their cross product.
        Vec3 row0(rotation[k].x, rotation[k].y, rotation[k].z), row1(rotation[k].w, velocity[k].w, angularMomentum[k].w);
        Vec3 row2 = row0.cross(row1);
        for (int j = 0; j < 3; j++) {
            s.rotation[0][j] = row0[j];
            s.rotation[1][j] = row1[j];
            s.rotation[2][j] = row2[j];
        }
    }
}

void CommonIntegrateRigidLangevinStepKernel::uploadBodyStates(ContextImpl& /*context*/, const vector<BodyState>& states) {
    if (numBodies == 0)
        return;
    ContextSelector selector(cc);
    if (mixedIsDouble)
        uploadStates<double, mm_double4>(states);
    else
        uploadStates<float, mm_float4>(states);
    // Setting positions may have changed the cell offsets without reordering atoms.
    updateAtomSlots();
    setBoxArguments();
    placeAtoms();
}

void CommonIntegrateRigidLangevinStepKernel::downloadBodyStates(ContextImpl& /*context*/, vector<BodyState>& states) {
    if (numBodies == 0) {
        states.clear();
        return;
    }
    ContextSelector selector(cc);
    if (mixedIsDouble)
        downloadStates<double, mm_double4>(states);
    else
        downloadStates<float, mm_float4>(states);
}

void CommonIntegrateRigidLangevinStepKernel::uploadCoefficients(ContextImpl& /*context*/, const vector<TypeStepCoefficients>& coefficients) {
    ContextSelector selector(cc);
    for (int t = 0; t < (int) coefficients.size(); t++) {
        const TypeStepCoefficients& c = coefficients[t];
        double* p = &hostTypeParams[TypeStride*t];
        for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) {
                p[ToModes+6*i+j] = c.toModes(i, j);
                p[FromModes+6*i+j] = c.fromModes(i, j);
                p[Friction+6*i+j] = c.friction(i, j);
                p[RandomForce+6*i+j] = c.randomForce(i, j);
            }
        for (int i = 0; i < 6; i++) {
            const ModeCoefficients& m = c.modes[i];
            double values[5] = {m.decay, m.drift, m.noiseVelocity, m.noiseCross, m.noiseDisplacement};
            for (int v = 0; v < 5; v++)
                p[Modes+5*i+v] = values[v];
            p[DriveFraction+i] = c.driveFraction[i];
            p[InverseMass+i] = c.inverseMass[i];
        }
        hostTypeInfo[t].z = (c.halfSteps ? 1 : 0);
    }
    uploadTypeParameters();
}

int CommonIntegrateRigidLangevinStepKernel::randomFloat4PerBody(int group, RigidLangevinIntegrator::Scheme scheme, bool frictionless) {
    if (frictionless)
        return 0;
    int rotations = stepGroupRotations(group);
    int numbers;
    if (scheme == RigidLangevinIntegrator::ExactFlow)
        numbers = (rotations == 0 ? 2 : 4)*(3+rotations);  // two per coordinate, for each half of the flow of rotating bodies
    else
        numbers = 3+rotations;                            // one per coordinate
    int float4s = (numbers+3)/4;
    if (float4s > MaxRandomFloat4PerBody)
        throw OpenMMException("RigidLangevinIntegrator: internal error: a step kernel loads at most "+std::to_string(MaxRandomFloat4PerBody)+
                              " float4s of random numbers per body, fewer than a body needs");
    return float4s;
}

void CommonIntegrateRigidLangevinStepKernel::takeStep(ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion) {
    ContextSelector selector(cc);
    const double h = integrator.getStepSize();
    const RigidLangevinIntegrator::Scheme scheme = integrator.getScheme();
    const bool frictionless = (integrator.getViscosity() == 0);
    if (numBodies > 0 && interactions && !frictionless)
        advanceCoupledBodies(context, integrator);  // no motion to remove: a CMMotionRemover is refused with friction
    else if (numBodies > 0) {
        if (removeMotion) {
            setMixedArg(centerOfMassKernel, 1, 1.0/model->getTotalMass(), mixedIsDouble);
            centerOfMassKernel->execute(ReductionGroupSize, ReductionGroupSize);
        }
        vector<ComputeKernel>& kernels = stepKernelsFor(scheme);
        if (periodic)
            setBoxArguments();
        for (int g = 0; g < NumStepGroups; g++) {
            int count = groupStart[g+1]-groupStart[g];
            if (count == 0)
                continue;
            int perBody = randomFloat4PerBody(g, scheme, frictionless);
            ComputeKernel& kernel = kernels[g];
            kernel->setArg(StepFirst, groupStart[g]);
            kernel->setArg(StepLast, groupStart[g+1]);
            kernel->setArg(StepFrictionless, frictionless ? 1 : 0);
            setMixedArg(kernel, StepSize, h, mixedIsDouble);
            kernel->setArg(StepRemoveMotion, removeMotion ? 1 : 0);
            kernel->setArg(StepRandomStep, randomStep);
            kernel->setArg(StepRandomPerBody, perBody);
            kernel->execute(count);
        }
        randomStep++;
    }
    finishHostStep(context, h);
}

std::function<double ()> CommonIntegrateRigidLangevinStepKernel::hostNormals() {
    // Four normal numbers per counter, the counters apart from the step kernels' (their draw index
    // is below MaxRandomFloat4PerBody), keyed by the seed and this step's randomStep.
    const unsigned int CoupledDraw = 0x48490000u;
    const unsigned int seed = randomSeed;
    const int step = randomStep++;
    std::shared_ptr<int> drawn = std::make_shared<int>(0);
    std::shared_ptr<std::array<float, 4> > normals = std::make_shared<std::array<float, 4> >();
    return [=] () {
        if (*drawn%4 == 0)
            normalFloat4(seed, *drawn/4, CoupledDraw, step, normals->data());
        return (double) (*normals)[(*drawn)++%4];
    };
}

BlobMobility& CommonIntegrateRigidLangevinStepKernel::blobMobility() {
    if (!deviceMobility)
        deviceMobility.reset(new CommonBlobMobility(cc, model->getIntegratorName()));
    return *deviceMobility;
}

void CommonIntegrateRigidLangevinStepKernel::parallelFor(int count, const std::function<void (int, int)>& task) {
    parallelForOn(cc.getThreadPool(), count, task);
}

SpectralBlobMobility* CommonIntegrateRigidLangevinStepKernel::createSpectralMobility(const std::string& integratorName,
                                                                                const KrylovSolvers::ParallelFor& parallel) {
    return new CommonPseMobility(cc, integratorName, parallel);
}

void CommonIntegrateRigidLangevinStepKernel::finishHostStep(ContextImpl& /*context*/, double h) {
    // The step kernels placed the bodies' sites with their bodies; OpenMM's kernel, which places
    // every site from its parents, is for sites outside bodies.
    if (model->hasSitesOutsideBodies())
        cc.getIntegrationUtilities().computeVirtualSites();
    cc.setTime(cc.getTime()+h);
    cc.setStepCount(cc.getStepCount()+1);
    cc.reorderAtoms();
}

void CommonIntegrateRigidLangevinStepKernel::computeBodyKineticEnergies(ContextImpl& /*context*/, double timeShift,
        double& translational, double& rotational, Vec3& momentum) {
    translational = rotational = 0;
    momentum = Vec3();
    if (numBodies == 0)
        return;
    ContextSelector selector(cc);
    setMixedArg(kineticEnergyKernel, 1, timeShift, mixedIsDouble);
    kineticEnergyKernel->execute(numReductionGroups*ReductionGroupSize, ReductionGroupSize);
    vector<mm_double4> sums;
    if (mixedIsDouble)
        kineticEnergies.download(sums);
    else {
        vector<mm_float4> values;
        kineticEnergies.download(values);
        for (const mm_float4& v : values)
            sums.push_back(mm_double4(v.x, v.y, v.z, v.w));
    }
    for (int g = 0; g < numReductionGroups; g++) {
        translational += sums[2*g].x;
        rotational += sums[2*g].y;
        momentum += Vec3(sums[2*g+1].x, sums[2*g+1].y, sums[2*g+1].z);
    }
}

void CommonIntegrateRigidLangevinStepKernel::createRandomCheckpoint(std::ostream& stream) {
    // The generator's whole state: its key and the counter's step.
    stream.write((char*) &randomSeed, sizeof(randomSeed));
    stream.write((char*) &randomStep, sizeof(randomStep));
}

void CommonIntegrateRigidLangevinStepKernel::loadRandomCheckpoint(std::istream& stream) {
    stream.read((char*) &randomSeed, sizeof(randomSeed));
    stream.read((char*) &randomStep, sizeof(randomStep));
    if (!stream)
        return;  // the caller reports a truncated checkpoint
    if (hasSetArguments)
        for (auto& scheme : stepKernels)
            for (ComputeKernel& kernel : scheme.second)
                kernel->setArg(StepRandomSeed, randomSeed);
}
