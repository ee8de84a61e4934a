#ifndef RIGID_BODY_TEST_UTILITIES_H_
#define RIGID_BODY_TEST_UTILITIES_H_

/*
 * Helpers shared by the C++ tests: systems of standard bodies, the rigid motion of a body measured
 * independently from its particles, statistics of correlated samples, and the platforms to run
 * on. Nothing here uses the plugin's internals (only the name of its kernel, to find the platforms
 * that have it), so the tests check the integrator from the outside.
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
    BodyShape(const std::vector<Eigen::Vector3d>& positions, const std::vector<double>& masses) : masses(masses) {
        double total = 0;
        Eigen::Vector3d com = Eigen::Vector3d::Zero();
        for (int i = 0; i < (int) masses.size(); i++) {
            com += masses[i]*positions[i];
            total += masses[i];
        }
        mass = total;
        com /= total;
        for (const Eigen::Vector3d& p : positions)
            reference.push_back(p-com);
        inertia = inertiaTensor(reference);
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(inertia);
        moments = eigen.eigenvalues();
        axes = eigen.eigenvectors();
    }
    Eigen::Matrix3d inertiaTensor(const std::vector<Eigen::Vector3d>& offsets) const {
        Eigen::Matrix3d t = Eigen::Matrix3d::Zero();
        for (int i = 0; i < (int) offsets.size(); i++)
            t += masses[i]*(offsets[i].squaredNorm()*Eigen::Matrix3d::Identity()-offsets[i]*offsets[i].transpose());
        return t;
    }
    /** Measure the body made of the given particles. */
    MeasuredBody measure(const std::vector<Vec3>& pos, const std::vector<Vec3>& vel, int firstParticle) const {
        MeasuredBody b;
        int n = masses.size();
        b.com.setZero();
        b.velocity.setZero();
        for (int i = 0; i < n; i++) {
            b.com += masses[i]*toEigen(pos[firstParticle+i]);
            b.velocity += masses[i]*toEigen(vel[firstParticle+i]);
        }
        b.com /= mass;
        b.velocity /= mass;
        Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
        Eigen::Vector3d angular = Eigen::Vector3d::Zero();
        std::vector<Eigen::Vector3d> offsets;
        for (int i = 0; i < n; i++) {
            Eigen::Vector3d d = toEigen(pos[firstParticle+i])-b.com;
            offsets.push_back(d);
            h += reference[i]*d.transpose();
            angular += masses[i]*d.cross(toEigen(vel[firstParticle+i])-b.velocity);
        }
        Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
        Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
        d(2, 2) = ((svd.matrixV()*svd.matrixU().transpose()).determinant() < 0 ? -1 : 1);
        b.rotation = svd.matrixV()*d*svd.matrixU().transpose();
        Eigen::Matrix3d labInertia = b.rotation*inertia*b.rotation.transpose();
        b.omega = pseudoSolve(labInertia, angular);
        return b;
    }
    /** The body-frame generalized velocity (V, omega) along the principal axes, mass-weighted. */
    Eigen::Matrix<double, 6, 1> weightedVelocity(const MeasuredBody& b) const {
        Eigen::Matrix3d principal = b.rotation*axes;
        Eigen::Matrix<double, 6, 1> u;
        u.head<3>() = std::sqrt(mass)*(principal.transpose()*b.velocity);
        Eigen::Vector3d w = principal.transpose()*b.omega;
        for (int k = 0; k < 3; k++)
            u[3+k] = std::sqrt(std::max(moments[k], 0.0))*w[k];
        return u;
    }
    static Eigen::Vector3d pseudoSolve(const Eigen::Matrix3d& a, const Eigen::Vector3d& b) {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(a);
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        double scale = eigen.eigenvalues().cwiseAbs().maxCoeff();
        for (int k = 0; k < 3; k++)
            if (eigen.eigenvalues()[k] > 1e-9*scale)
                x += eigen.eigenvectors().col(k)*(eigen.eigenvectors().col(k).dot(b)/eigen.eigenvalues()[k]);
        return x;
    }
    std::vector<double> masses;
    std::vector<Eigen::Vector3d> reference;
    double mass;
    Eigen::Matrix3d inertia, axes;
    Eigen::Vector3d moments;
};

/** An asymmetric four-particle body (all principal moments different). */
inline BodyShape asymmetricBody() {
    return BodyShape({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.12, 0, 0), Eigen::Vector3d(0.02, 0.09, 0), Eigen::Vector3d(0.03, 0.02, 0.07)},
                     {16.0, 12.0, 14.0, 30.0});
}

/** A regular tetrahedron of equal masses: isotropic inertia. */
inline BodyShape tetrahedron(double radius, double particleMass) {
    double a = radius/std::sqrt(3.0);
    return BodyShape({Eigen::Vector3d(a, a, a), Eigen::Vector3d(a, -a, -a), Eigen::Vector3d(-a, a, -a), Eigen::Vector3d(-a, -a, a)},
                     std::vector<double>(4, particleMass));
}

/**
 * Add `count` bodies of `shape` to the System and the integrator, in a row along x 1 nm apart,
 * every particle of radius `radius`; returns their particles' positions.
 */
inline std::vector<Vec3> addBodiesInARow(OpenMM::System& system, RigidLangevinPlugin::RigidLangevinIntegrator& integrator, const BodyShape& shape,
        int count, double radius) {
    std::vector<Vec3> positions;
    for (int b = 0; b < count; b++) {
        std::vector<int> particles;
        for (int i = 0; i < (int) shape.masses.size(); i++) {
            particles.push_back(system.addParticle(shape.masses[i]));
            integrator.setParticleRadius(particles.back(), radius);
            positions.push_back(toVec3(shape.reference[i]+Eigen::Vector3d(b, 0, 0)));
        }
        integrator.addRigidBody(particles);
    }
    return positions;
}

/**
 * A fixed, symmetric positive definite 6x6 resistance tensor (per unit viscosity) with strong
 * translation-rotation coupling at its own origin.
 */
inline Eigen::Matrix<double, 6, 6> coupledTensor() {
    Eigen::Matrix<double, 6, 6> a;
    a << 1.0, 0.3, -0.2, 0.5, -0.1, 0.2,
         0.1, 0.9, 0.4, -0.3, 0.6, 0.1,
         -0.2, 0.2, 1.1, 0.2, 0.1, -0.5,
         0.3, -0.4, 0.1, 1.2, 0.2, 0.3,
         0.2, 0.1, -0.3, 0.1, 0.8, -0.2,
         -0.1, 0.3, 0.2, -0.2, 0.3, 1.0;
    Eigen::Matrix<double, 6, 1> scale;
    scale << 2.5, 2.5, 2.5, 0.3, 0.3, 0.3;
    Eigen::Matrix<double, 6, 6> xi = a*a.transpose()+0.5*Eigen::Matrix<double, 6, 6>::Identity();
    return scale.asDiagonal()*xi*scale.asDiagonal();
}

/** Move the reference point of a mobility (diffusion) tensor by r: B mu B^T, B = [[1, -skew(r)], [0, 1]]. */
inline Eigen::Matrix<double, 6, 6> moveMobility(const Eigen::Matrix<double, 6, 6>& mu, const Eigen::Vector3d& r) {
    Eigen::Matrix<double, 6, 6> b = Eigen::Matrix<double, 6, 6>::Identity();
    b.block<3, 3>(0, 3) = -skew(r);
    return b*mu*b.transpose();
}

/**
 * The centre of diffusion of a mobility tensor, relative to its reference point: the point where
 * the trace of the translational block is least (its coupling block is symmetric there).
 * tr(tt(r)) is quadratic in r: tr(tt) - 2 tr(skew(r) rt) - tr(skew(r) rr skew(r)).
 */
inline Eigen::Vector3d centerOfDiffusion(const Eigen::Matrix<double, 6, 6>& mu) {
    auto trace = [&](const Eigen::Vector3d& r) {
        return moveMobility(mu, r).block<3, 3>(0, 0).trace();
    };
    Eigen::Matrix3d hessian;
    Eigen::Vector3d gradient;
    double e = 1e-3;
    for (int i = 0; i < 3; i++) {
        Eigen::Vector3d ei = Eigen::Vector3d::Unit(i)*e;
        gradient[i] = (trace(ei)-trace(-ei))/(2*e);
        for (int j = 0; j < 3; j++) {
            Eigen::Vector3d ej = Eigen::Vector3d::Unit(j)*e;
            hessian(i, j) = (trace(ei+ej)-trace(ei-ej)-trace(-ei+ej)+trace(-ei-ej))/(4*e*e);
        }
    }
    return -hessian.ldlt().solve(gradient);
}

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
    double mean() const {
        double sum = 0;
        for (double v : values)
            sum += v;
        return sum/values.size();
    }
    double standardError(int numBlocks = 16) const {
        numBlocks = std::max(2, std::min(numBlocks, (int) values.size()/(2*overlap)));
        int size = values.size()/numBlocks;
        double m = mean(), sum = 0;
        for (int b = 0; b < numBlocks; b++) {
            double blockMean = 0;
            for (int i = 0; i < size; i++)
                blockMean += values[b*size+i];
            blockMean /= size;
            sum += (blockMean-m)*(blockMean-m);
        }
        return std::sqrt(sum/(numBlocks*(numBlocks-1.0)));
    }
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

/**
 * The standard deviation of the total energy sampled `samples` times, `every` steps apart: the
 * energy error of a run without friction.
 */
inline double energyFluctuation(OpenMM::Context& context, OpenMM::Integrator& integrator, int every, int samples) {
    std::vector<double> energy;
    for (int i = 0; i < samples; i++) {
        integrator.step(every);
        OpenMM::State s = context.getState(OpenMM::State::Energy);
        energy.push_back(s.getKineticEnergy()+s.getPotentialEnergy());
    }
    double mean = 0, square = 0;
    for (double e : energy)
        mean += e/samples;
    for (double e : energy)
        square += (e-mean)*(e-mean)/samples;
    return std::sqrt(square);
}

/** Every body's state from a Context: positions and velocities of all particles. */
inline void getParticles(OpenMM::Context& context, std::vector<Vec3>& pos, std::vector<Vec3>& vel) {
    OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Velocities);
    pos = state.getPositions();
    vel = state.getVelocities();
}

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

inline std::ostream& operator<<(std::ostream& out, const PlatformConfig& config) {
    return out << config.name();
}

/**
 * The platform under test as test parameters: GPU platforms in each of the given precisions,
 * Reference and CPU (which compute in double precision) once.
 */
inline std::vector<PlatformConfig> platformConfigs(const std::vector<std::string>& gpuPrecisions = {"double"}) {
    PlatformConfig c;
    c.platform = platformUnderTest().name;
    c.precision = "double";
    if (!c.isGPU())
        return {c};
    std::vector<PlatformConfig> configs;
    for (const std::string& precision : gpuPrecisions) {
        c.precision = precision;
        configs.push_back(c);
    }
    return configs;
}

/** What is compared with Reference: the platform under test in all its precisions, unless it is Reference. */
inline std::vector<PlatformConfig> nonReferenceConfigs() {
    if (platformUnderTest().name == "Reference")
        return {};
    return platformConfigs({"single", "mixed", "double"});
}

/** A GPU platform in single and mixed precision: the statistical tests' representative cases run there too. */
inline std::vector<PlatformConfig> lowerPrecisionConfigs() {
    std::vector<PlatformConfig> configs;
    for (const PlatformConfig& c : platformConfigs({"single", "mixed"}))
        if (c.isGPU())
            configs.push_back(c);
    return configs;
}

/**
 * Whether the statistical tests run all their cases on a platform, or one representative case per
 * test. Reference defines the physics and the GPU platforms reimplement it (their own kernels), so
 * they run every case. The CPU platform runs the Reference's own per-body code (BodyDynamics.h);
 * what it adds is its threading and its random number streams, which one case per test checks, and
 * its per-step overhead (OpenMM's CPU platform: ~0.2 ms a step) would make every case slow.
 */
inline bool runsEveryStatisticalCase(const PlatformConfig& config) {
    return config.platform != "CPU" && config.precision == "double";
}

/** A gtest parameter name for a PlatformConfig. */
struct PlatformConfigName {
    template <class ParamInfo>
    std::string operator()(const ParamInfo& info) const {
        return info.param.name();
    }
};

/** A Context on a platform in its precision. */
inline OpenMM::Context* createContext(OpenMM::System& system, OpenMM::Integrator& integrator, const PlatformConfig& config) {
    return new OpenMM::Context(system, integrator, config.get(), config.properties());
}

} // namespace RigidBodyTest

#endif /*RIGID_BODY_TEST_UTILITIES_H_*/
