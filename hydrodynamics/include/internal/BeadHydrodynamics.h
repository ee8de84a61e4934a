#ifndef RIGID_LANGEVIN_BEAD_HYDRODYNAMICS_H_
#define RIGID_LANGEVIN_BEAD_HYDRODYNAMICS_H_

#include "internal/ResistanceMath.h"
#include "internal/windowsExportHydrodynamics.h"
#include "openmm/Vec3.h"
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The resistance tensor of a rigid assembly of spherical beads with hydrodynamic interaction:
 * bead velocities are B f for bead forces f, with B the 3N x 3N generalised Rotne-Prager-Yamakawa
 * mobility (see RotnePragerYamakawa.h), and Xi = P^T B^-1 P with P the 3N x 6 matrix of rigid
 * motions. B is Cholesky-factorised and solved for the six columns of P; it is never inverted.
 * Cost: 9 N^2 doubles of memory allocated, of which the half that holds the lower triangle is
 * touched, and 9 N^3 flops.
 */
namespace BeadHydrodynamics {

/** Which build of the dense kernel to use. */
enum Kernel {
    /** AVX2/FMA where the library has it and the CPU supports it, otherwise baseline. */
    AutomaticKernel,
    /** The baseline x86-64 (or other architecture's default) build. */
    GenericKernel,
    /** The AVX2/FMA build; throws if it is unavailable (see isAVX2KernelAvailable()). */
    AVX2Kernel
};

/**
 * How many threads the kernel uses: the environment variable OPENMM_CPU_THREADS if it is set to a
 * positive number (as for OpenMM's CPU platform), otherwise the number of logical cores. The
 * threads live only while a tensor is computed.
 */
OPENMM_EXPORT_HYDRODYNAMICS int getNumThreads();

/** Whether the AVX2 kernel was built and this CPU (and operating system) can run it. */
OPENMM_EXPORT_HYDRODYNAMICS bool isAVX2KernelAvailable();

/**
 * The Cholesky factorisation A = L L^T in place in the lower triangle of the n x n column-major
 * matrix lower (the strict upper triangle neither read nor written), by the kernel's blocked
 * factorisation on numThreads threads, in its AVX2/FMA build where the CPU has it. The result
 * does not depend on numThreads. Returns false if A is not numerically positive definite; throws
 * an OpenMMException if it does not fit in memory.
 */
OPENMM_EXPORT_HYDRODYNAMICS bool choleskyInPlace(int n, double* lower, int numThreads);

/** The name of bead i in messages (such as "blob 2 of body 1"); where none is given, "bead i". */
typedef std::function<std::string (int bead)> BeadNames;

/**
 * Throw an OpenMMException, whose message starts with caller, unless the bead model is usable: at
 * least one bead, as many radii as positions, finite positions, positive finite radii, and no two
 * beads coincident (the same position and radius to 1e-10 of the radius: the same sphere twice
 * would make B singular). The message names the offending bead or beads, by names if given.
 */
OPENMM_EXPORT_HYDRODYNAMICS void validate(const std::string& caller, const std::vector<OpenMM::Vec3>& positions,
                                          const std::vector<double>& radii, const BeadNames& names = BeadNames());

/**
 * A pair (i < j) of beads that are the same sphere, |difference(i, j)| and |radii[i] - radii[j]|
 * both within 1e-10 of the larger radius, or (-1, -1) if there is none. Candidates are found by
 * sorting keys: a coordinate of each bead (nm) whose difference between two beads |difference|
 * cannot be shorter than; with period > 0 the keys lie in [0, period) and wrap around (the width
 * of a periodic box across the planes they measure along).
 */
OPENMM_EXPORT_HYDRODYNAMICS std::pair<int, int> findCoincident(const std::vector<double>& keys, double period,
                                                               const std::function<OpenMM::Vec3 (int i, int j)>& difference,
                                                               const std::vector<double>& radii);

/**
 * The resistance tensor per unit viscosity of the bead model about origin (convention of
 * ResistanceTensor), after validate(). If B is not numerically positive definite it falls back to
 * a pivoted LDL^T factorisation and warns on std::cerr. Throws if the matrix cannot be held in
 * memory or factorised.
 */
OPENMM_EXPORT_HYDRODYNAMICS ResistanceMath::Matrix6 resistance(const std::string& caller, const std::vector<OpenMM::Vec3>& positions,
                                                               const std::vector<double>& radii, const OpenMM::Vec3& origin,
                                                               Kernel kernel = AutomaticKernel);

} // namespace BeadHydrodynamics
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BEAD_HYDRODYNAMICS_H_*/
