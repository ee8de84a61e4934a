// The helpers of RigidBodyTestUtilities.h, compiled once (into RigidLangevinTestMain, which every
// test executable links) rather than in each test: their Eigen solvers took about 6 s of every
// test file's compile time.
#include "RigidBodyTestUtilities.h"
#include "openmm/OpenMMException.h"
#include "openmm/VerletIntegrator.h"
#include <gtest/gtest.h>

namespace RigidBodyTest {

BodyShape::BodyShape(const std::vector<Eigen::Vector3d>& positions, const std::vector<double>& masses) : masses(masses) {
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

Eigen::Matrix3d BodyShape::inertiaTensor(const std::vector<Eigen::Vector3d>& offsets) const {
    Eigen::Matrix3d t = Eigen::Matrix3d::Zero();
    for (int i = 0; i < (int) offsets.size(); i++)
        t += masses[i]*(offsets[i].squaredNorm()*Eigen::Matrix3d::Identity()-offsets[i]*offsets[i].transpose());
    return t;
}

MeasuredBody BodyShape::measure(const std::vector<Vec3>& pos, const std::vector<Vec3>& vel, int firstParticle) const {
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
    for (int i = 0; i < n; i++) {
        Eigen::Vector3d d = toEigen(pos[firstParticle+i])-b.com;
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

Eigen::Matrix<double, 6, 1> BodyShape::weightedVelocity(const MeasuredBody& b) const {
    Eigen::Matrix3d principal = b.rotation*axes;
    Eigen::Matrix<double, 6, 1> u;
    u.head<3>() = std::sqrt(mass)*(principal.transpose()*b.velocity);
    Eigen::Vector3d w = principal.transpose()*b.omega;
    for (int k = 0; k < 3; k++)
        u[3+k] = std::sqrt(std::max(moments[k], 0.0))*w[k];
    return u;
}

Eigen::Vector3d BodyShape::pseudoSolve(const Eigen::Matrix3d& a, const Eigen::Vector3d& b) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(a);
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    double scale = eigen.eigenvalues().cwiseAbs().maxCoeff();
    for (int k = 0; k < 3; k++)
        if (eigen.eigenvalues()[k] > 1e-9*scale)
            x += eigen.eigenvectors().col(k)*(eigen.eigenvectors().col(k).dot(b)/eigen.eigenvalues()[k]);
    return x;
}

BodyShape asymmetricBody() {
    return BodyShape({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.12, 0, 0), Eigen::Vector3d(0.02, 0.09, 0), Eigen::Vector3d(0.03, 0.02, 0.07)},
                     {16.0, 12.0, 14.0, 30.0});
}

BodyShape tetrahedron(double radius, double particleMass) {
    double a = radius/std::sqrt(3.0);
    return BodyShape({Eigen::Vector3d(a, a, a), Eigen::Vector3d(a, -a, -a), Eigen::Vector3d(-a, a, -a), Eigen::Vector3d(-a, -a, a)},
                     std::vector<double>(4, particleMass));
}

std::vector<Vec3> addBodiesInARow(OpenMM::System& system, RigidLangevinPlugin::RigidLangevinIntegrator& integrator, const BodyShape& shape,
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

Eigen::Matrix<double, 6, 6> coupledTensor() {
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

Eigen::Matrix<double, 6, 6> moveMobility(const Eigen::Matrix<double, 6, 6>& mu, const Eigen::Vector3d& r) {
    Eigen::Matrix<double, 6, 6> b = Eigen::Matrix<double, 6, 6>::Identity();
    b.block<3, 3>(0, 3) = -skew(r);
    return b*mu*b.transpose();
}

Eigen::Vector3d centerOfDiffusion(const Eigen::Matrix<double, 6, 6>& mu) {
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

std::vector<double> sampleTotalEnergy(OpenMM::Context& context, OpenMM::Integrator& integrator, int every, int samples) {
    std::vector<double> energy;
    for (int i = 0; i < samples; i++) {
        integrator.step(every);
        OpenMM::State s = context.getState(OpenMM::State::Energy);
        energy.push_back(s.getKineticEnergy()+s.getPotentialEnergy());
    }
    return energy;
}

double energyFluctuation(OpenMM::Context& context, OpenMM::Integrator& integrator, int every, int samples) {
    std::vector<double> energy = sampleTotalEnergy(context, integrator, every, samples);
    double mean = 0, square = 0;
    for (double e : energy)
        mean += e/samples;
    for (double e : energy)
        square += (e-mean)*(e-mean)/samples;
    return std::sqrt(square);
}

void getParticles(OpenMM::Context& context, std::vector<Vec3>& pos, std::vector<Vec3>& vel) {
    OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Velocities);
    pos = state.getPositions();
    vel = state.getVelocities();
}

double maxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double worst = 0;
    for (int i = 0; i < (int) a.size(); i++)
        worst = std::max(worst, std::sqrt((a[i]-b[i]).dot(a[i]-b[i])));
    return worst;
}

std::ostream& operator<<(std::ostream& out, const PlatformConfig& config) {
    return out << config.name();
}

std::vector<PlatformConfig> platformConfigs(const std::vector<std::string>& gpuPrecisions) {
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

std::vector<PlatformConfig> nonReferenceConfigs() {
    if (platformUnderTest().name == "Reference")
        return {};
    return platformConfigs({"single", "mixed", "double"});
}

std::vector<PlatformConfig> lowerPrecisionConfigs() {
    std::vector<PlatformConfig> configs;
    for (const PlatformConfig& c : platformConfigs({"single", "mixed"}))
        if (c.isGPU())
            configs.push_back(c);
    return configs;
}

namespace {

/** Whether an OpenCL platform runs on PoCL, the host's cores standing in for a GPU (read once). */
bool emulatedOnTheHost(const PlatformConfig& config) {
    if (config.platform != "OpenCL")
        return false;
    static const bool emulated = [&] () {
        OpenMM::System system;
        system.addParticle(1.0);
        OpenMM::VerletIntegrator integrator(0.001);
        OpenMM::Context context(system, integrator, config.get(), config.properties());
        return config.get().getPropertyValue(context, "OpenCLPlatformName").find("Portable Computing Language") != std::string::npos;
    }();
    return emulated;
}

} // namespace

bool runsEveryStatisticalCase(const PlatformConfig& config) {
    return config.platform != "CPU" && config.precision == "double" && !emulatedOnTheHost(config);
}

OpenMM::Context* createContext(OpenMM::System& system, OpenMM::Integrator& integrator, const PlatformConfig& config) {
    return new OpenMM::Context(system, integrator, config.get(), config.properties());
}

void expectError(const std::function<void ()>& action, const std::vector<std::string>& fragments) {
    try {
        action();
        ADD_FAILURE() << "expected an OpenMMException mentioning '" << fragments[0] << "'";
    }
    catch (const OpenMM::OpenMMException& e) {
        std::string message = e.what();
        for (const std::string& fragment : fragments)
            EXPECT_NE(std::string::npos, message.find(fragment)) << "message: " << message;
    }
}

double Series::mean() const {
    double sum = 0;
    for (double v : values)
        sum += v;
    return sum/values.size();
}

double Series::standardError(int numBlocks) const {
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

} // namespace RigidBodyTest
