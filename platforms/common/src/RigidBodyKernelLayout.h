#ifndef RIGID_BODY_KERNEL_LAYOUT_H_
#define RIGID_BODY_KERNEL_LAYOUT_H_

#include "CommonRigidLangevinKernelSources.h"
#include "RigidLangevinIntegrator.h"
#include "internal/BodyDynamics.h"
#include <map>
#include <sstream>
#include <string>

namespace RigidLangevinPlugin {

/**
 * What the host code and the device kernels of the common platforms (the .cc files in src/kernels) must agree
 * on: the layout of the per-type parameters and the compile-time constants. Kept apart from the
 * kernel class so that a test can compile the device source without a device (TestCudaKernelSources).
 */
namespace RigidBodyKernelLayout {

/** Offsets of the parameters of one body type in the typeParams array, TypeStride values per type. */
enum TypeParameter {
    ToModes = 0,           ///< 36: TypeStepCoefficients::toModes, row-major
    FromModes = 36,        ///< 36: fromModes
    Modes = 72,            ///< 6 x 5: decay, drift, noiseVelocity, noiseCross, noiseDisplacement
    DriveFraction = 102,   ///< 6: driveFraction per generalized coordinate
    MassAndInertia = 108,  ///< 4: mass and the three principal moments
    Friction = 112,        ///< 36: the Original scheme's friction
    RandomForce = 148,     ///< 36: the Original scheme's random force factor
    InverseMass = 184,     ///< 6: the Original scheme's inverse masses
    TypeStride = 190
};

/**
 * The most float4s of normal random numbers a body takes in one step (ExactFlow's two halves for six
 * coordinates: 24 numbers): the step kernels load this many with a constant loop bound, so that
 * the numbers stay in registers.
 */
const int MaxRandomFloat4PerBody = 6;

/** Work items per group of the reduction kernels. */
const int ReductionGroupSize = 128;

/**
 * Bodies are stepped in groups of one friction class and one number of rotations (0, 2 or 3), each
 * group by a kernel compiled for it: a class never pays for another's work, and with the number of
 * coordinates known at compile time the per-body arrays stay in registers.
 */
const int NumStepGroups = 7;

/** The step group of a body type. */
inline int stepGroup(FrictionClass frictionClass, int numRotations) {
    if (frictionClass == FrictionClass::Scalar)
        return 0;
    int rotations = (numRotations == 0 ? 0 : numRotations == 2 ? 1 : 2);
    return (frictionClass == FrictionClass::Diagonal ? 1 : 4)+rotations;
}

/** The number of rotations of the bodies of a step group. */
inline int stepGroupRotations(int group) {
    static const int rotations[NumStepGroups] = {0, 0, 2, 3, 0, 2, 3};
    return rotations[group];
}

/** The name of the kernel that steps a group (rigidBodyStep.cc). */
inline std::string stepKernelName(int group) {
    static const char* names[NumStepGroups] = {"stepScalarBodies", "stepDiagonalBodies0", "stepDiagonalBodies2", "stepDiagonalBodies3",
                                               "stepCoupledBodies0", "stepCoupledBodies2", "stepCoupledBodies3"};
    return names[group];
}

/** The device source: every kernel file, in the order they depend on each other. */
inline std::string source() {
    return CommonRigidLangevinKernelSources::rigidBodyMath+CommonRigidLangevinKernelSources::rigidBodyAtoms+
           CommonRigidLangevinKernelSources::rigidBodyRandom+CommonRigidLangevinKernelSources::rigidBodyStep+
           CommonRigidLangevinKernelSources::rigidBodyReductions;
}

/**
 * The preprocessor definitions the source needs.
 *
 * @param paddedNumAtoms  the context's padded number of atoms (the force buffer's stride)
 * @param mixedIsDouble   whether the device's "mixed" type is double (literals get no f suffix)
 * @param scheme          the scheme the step kernels are compiled for (STEP_SCHEME; its value is
 *                        the SCHEME_* constant of rigidBodyStep.cc)
 */
inline std::map<std::string, std::string> defines(int paddedNumAtoms, bool mixedIsDouble, RigidLangevinIntegrator::Scheme scheme) {
    std::map<std::string, std::string> d;
    d["STEP_SCHEME"] = std::to_string((int) scheme);
    d["PADDED_NUM_ATOMS"] = std::to_string(paddedNumAtoms);
    d["TYPE_STRIDE"] = std::to_string((int) TypeStride);
    d["TP_TO_MODES"] = std::to_string((int) ToModes);
    d["TP_FROM_MODES"] = std::to_string((int) FromModes);
    d["TP_MODES"] = std::to_string((int) Modes);
    d["TP_DRIVE"] = std::to_string((int) DriveFraction);
    d["TP_MASS"] = std::to_string((int) MassAndInertia);
    d["TP_FRICTION"] = std::to_string((int) Friction);
    d["TP_RANDOM_FORCE"] = std::to_string((int) RandomForce);
    d["TP_INVERSE_MASS"] = std::to_string((int) InverseMass);
    d["REDUCTION_GROUP_SIZE"] = std::to_string(ReductionGroupSize);
    d["MAX_RANDOM_FLOAT4_PER_BODY"] = std::to_string(MaxRandomFloat4PerBody);
    d["ORIGINAL_MAX_ITERATIONS"] = std::to_string(BodyDynamics::OriginalSchemeMaxIterations);
    std::ostringstream tolerance;
    tolerance.precision(17);
    tolerance << std::scientific << BodyDynamics::OriginalSchemeTolerance << (mixedIsDouble ? "" : "f");
    d["ORIGINAL_TOLERANCE"] = tolerance.str();
    return d;
}

} // namespace RigidBodyKernelLayout
} // namespace RigidLangevinPlugin

#endif /*RIGID_BODY_KERNEL_LAYOUT_H_*/
