#ifndef RIGID_BODY_TEST_UTILITIES_H_
#define RIGID_BODY_TEST_UTILITIES_H_

/*
 * Helpers shared by the C++ tests: systems of standard bodies, the rigid motion of a body measured
 * independently from its particles, statistics of correlated samples, and the platforms to run
 * on. Nothing here uses the plugin's internals (only the name of its kernel, to find the platforms
 * that have it), so the tests check the integrator from the outside. The larger functions are
 * defined in RigidBodyTestUtilities.cpp, compiled once.
 */

#include "PlatformUnderTest.h"
#include "RigidLangevinIntegrator.h"
#include "RigidLangevinKernels.h"
#include "openmm/Context.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace RigidBodyTest {

using OpenMM::Vec3;

const double BOLTZ = 0.0083144626181532;  // kJ/(mol K)

inline Eigen::Vector3d toEigen(const Vec3& v) {
    return Eigen::Vector3d(v[0], v[1], v[2]);
}

inline Vec3 toVec3(const Eigen::Vector3d& v) {
    return Vec3(v[0], v[1], v[2]);
}

inline Eigen::Matrix3d skew(const Eigen::Vector3d& r) {
    Eigen::Matrix3d s;
    s << 0, -r[2], r[1], r[2], 0, -r[0], -r[1], r[0], 0;
    return s;
}

/** 36 row-major values of a 6x6 matrix. */
inline std::vector<double> flatten(const Eigen::Matrix<double, 6, 6>& m) {
    std::vector<double> v(36);
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++)
            v[6*i+j] = m(i, j);
    return v;
}

/**
 * A rigid body as its particles show it: centre of mass, the rotation A with
 * (r_i - com) = A (ref_i - refCom), velocity and lab angular velocity.
 */
struct MeasuredBody {
    Eigen::Vector3d com, velocity, omega;
    Eigen::Matrix3d rotation;
};

/**
 * The reference shape of a body (positions of its particles and their masses) and the way to
 * measure the body's rigid motion from particle positions and velocities.
 */
class BodyShape {
public:
    BodyShape(const std::vector<Eigen::Vector3d>& positions, const std::vector<double>& masses);
    Eigen::Matrix3d inertiaTensor(const std::vector<Eigen::Vector3d>& offsets) const;
    /** Measure the body made of the given particles. */
    MeasuredBody measure(const std::vector<Vec3>& pos, const std::vector<Vec3>& vel, int firstParticle) const;
    /** The body-frame generalized velocity (V, omega) along the principal axes, mass-weighted. */
    Eigen::Matrix<double, 6, 1> weightedVelocity(const MeasuredBody& b) const;
    /** x = a^+ b for a symmetric a, eigenvalues up to 1e-9 of the largest counting as zero (a linear body's inertia). */
    static Eigen::Vector3d pseudoSolve(const Eigen::Matrix3d& a, const Eigen::Vector3d& b);
    std::vector<double> masses;
    std::vector<Eigen::Vector3d> reference;
    double mass;
    Eigen::Matrix3d inertia, axes;
    Eigen::Vector3d moments;
};

/** An asymmetric four-particle body (all principal moments different). */
BodyShape asymmetricBody();

/** A regular tetrahedron of equal masses: isotropic inertia. */
BodyShape tetrahedron(double radius, double particleMass);

/**
 * Add `count` bodies of `shape` to the System and the integrator, in a row along x 1 nm apart,
 * every particle of radius `radius`; returns their particles' positions.
 */
std::vector<Vec3> addBodiesInARow(OpenMM::System& system, RigidLangevinPlugin::RigidLangevinIntegrator& integrator, const BodyShape& shape,
        int count, double radius);

/**
 * A fixed, symmetric positive definite 6x6 resistance tensor (per unit viscosity) with strong
 * translation-rotation coupling at its own origin.
 */
Eigen::Matrix<double, 6, 6> coupledTensor();

/** Move the reference point of a mobility (diffusion) tensor by r: B mu B^T, B = [[1, -skew(r)], [0, 1]]. */
Eigen::Matrix<double, 6, 6> moveMobility(const Eigen::Matrix<double, 6, 6>& mu, const Eigen::Vector3d& r);

/**
 * The centre of diffusion of a mobility tensor, relative to its reference point: the point where
 * the trace of the translational block is least (its coupling block is symmetric there).
 * tr(tt(r)) is quadratic in r: tr(tt) - 2 tr(skew(r) rt) - tr(skew(r) rr skew(r)).
 */
Eigen::Vector3d centerOfDiffusion(const Eigen::Matrix<double, 6, 6>& mu);

/**
 * Mean and standard error of a time series of correlated samples, by block averaging: the samples
 * are split into blocks longer than the correlation time and the spread of block means gives the
 * error. Each sample should already be an average over independent bodies.
 */
struct Series {
    std::vector<double> values;
    /** How many consecutive values share data (a correlation over time origins at lag L: L+1). Blocks
     * are kept at least twice that long, or adjacent blocks would share most of their data and the
     * error would come out too small. */
    int overlap = 1;
    void add(double v) {
        values.push_back(v);
    }
    double mean() const;
    double standardError(int numBlocks = 16) const;
};

/**
 * f(i, i+lag, b) averaged over the time origins i of a run of numSamples samples and over the
 * bodies b of each of numGroups groups (b = g, g+numGroups, ...): a Series of independent values
 * where the bodies do not interact, so that its standard error is that of their mean. Blocks of
 * time origins are neither independent nor many: in SphereDynamics' orientational correlation their
 * errors came out between half and twice those from groups of bodies in the same runs.
 */
template <class F>
Series averageOverBodyGroups(int numGroups, int numBodies, int numSamples, int lag, F f) {
    Series s;
    for (int g = 0; g < numGroups; g++) {
        double sum = 0;
        int count = 0;
        for (int b = g; b < numBodies; b += numGroups)
            for (int i = 0; i+lag < numSamples; i++, count++)
                sum += f(i, i+lag, b);
        s.add(sum/count);
    }
    return s;
}

/** The total energy (kinetic plus potential) after each of `samples` runs of `every` steps. */
std::vector<double> sampleTotalEnergy(OpenMM::Context& context, OpenMM::Integrator& integrator, int every, int samples);

/**
 * The standard deviation of the total energy sampled `samples` times, `every` steps apart: the
 * energy error of a run without friction.
 */
double energyFluctuation(OpenMM::Context& context, OpenMM::Integrator& integrator, int every, int samples);

/** Every body's state from a Context: positions and velocities of all particles. */
void getParticles(OpenMM::Context& context, std::vector<Vec3>& pos, std::vector<Vec3>& vel);

/** The largest distance between corresponding positions of two configurations. */
double maxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

/** A platform and the precision to run it in. */
struct PlatformConfig {
    std::string platform;
    std::string precision;  ///< "single", "mixed" or "double" (Reference and CPU: "double")
    /** A name for test output and gtest parameters, e.g. "OpenCL_mixed". */
    std::string name() const {
        return platform+"_"+precision;
    }
    bool isGPU() const {
        return platform == "OpenCL" || platform == "CUDA" || platform == "HIP";
    }
    std::map<std::string, std::string> properties() const {
        std::map<std::string, std::string> p;
        if (isGPU())
            p["Precision"] = precision;
        return p;
    }
    OpenMM::Platform& get() const {
        return OpenMM::Platform::getPlatformByName(platform);
    }
};

std::ostream& operator<<(std::ostream& out, const PlatformConfig& config);

/**
 * The platform under test as test parameters: GPU platforms in each of the given precisions,
 * Reference and CPU (which compute in double precision) once.
 */
std::vector<PlatformConfig> platformConfigs(const std::vector<std::string>& gpuPrecisions = {"double"});

/** What is compared with Reference: the platform under test in all its precisions, unless it is Reference. */
std::vector<PlatformConfig> nonReferenceConfigs();

/** A GPU platform in single and mixed precision: the statistical tests' representative cases run there too. */
std::vector<PlatformConfig> lowerPrecisionConfigs();

/**
 * Whether the statistical tests run all their cases on a platform, or one representative case per
 * test. Reference defines the physics and the GPU platforms reimplement it (their own kernels), so
 * they run every case on a GPU. The CPU platform runs the Reference's own per-body code
 * (BodyDynamics.h); what it adds is its threading and its random number streams, which one case per
 * test checks, and its per-step overhead (OpenMM's CPU platform: ~0.2 ms a step) would make every
 * case slow. OpenCL on PoCL (the host's cores, as on CI) runs the representative case too: the
 * cases differ in their friction (gamma h from 1e-3 to 1e3), whose coefficients the host computes
 * for every platform and Reference checks in every case; the kernels apply them with the same
 * arithmetic in each, and the every-case runs took some 150 s of PoCL's time (a sixth of ctest's).
 */
bool runsEveryStatisticalCase(const PlatformConfig& config);

/** A gtest parameter name for a PlatformConfig. */
struct PlatformConfigName {
    template <class ParamInfo>
    std::string operator()(const ParamInfo& info) const {
        return info.param.name();
    }
};

/**
 * An integrator of class Base that shows a test its Context's ContextImpl (Integrator::context is
 * protected), for the tests that read a platform's own arrays or run its kernels' parts directly.
 */
template <class Base> class WithContextImpl : public Base {
public:
    using Base::Base;
    OpenMM::ContextImpl& contextImpl() {
        return *this->context;
    }
};

/** A Context on a platform in its precision. */
OpenMM::Context* createContext(OpenMM::System& system, OpenMM::Integrator& integrator, const PlatformConfig& config);

/** Expect action to throw an OpenMMException whose message contains every one of fragments. */
void expectError(const std::function<void ()>& action, const std::vector<std::string>& fragments);

/**
 * An environment variable set while in scope, for the Contexts made then, and put back as it was
 * after (unset if it was), also when a test throws or an ASSERT returns early: the kernels read
 * these settings when a Context is made or a step taken, so a setting left behind would change the
 * tests that follow in the same process.
 */
struct EnvironmentSetting {
    EnvironmentSetting(const char* name, const char* value) : name(name) {
        const char* previous = std::getenv(name);
        wasSet = (previous != NULL);
        if (wasSet)
            saved = previous;
        setenv(name, value, 1);
    }
    ~EnvironmentSetting() {
        if (wasSet)
            setenv(name.c_str(), saved.c_str(), 1);
        else
            unsetenv(name.c_str());
    }
    std::string name, saved;
    bool wasSet;
};

/**
 * RIGIDLANGEVIN_HOST_PARTICLE_STORES (how the host step writes particles: auto, cached or
 * streaming) set while in scope (ctest sets none).
 */
struct ParticleStoresSetting : EnvironmentSetting {
    explicit ParticleStoresSetting(const char* value) : EnvironmentSetting("RIGIDLANGEVIN_HOST_PARTICLE_STORES", value) {
    }
};

} // namespace RigidBodyTest

#endif /*RIGID_BODY_TEST_UTILITIES_H_*/
