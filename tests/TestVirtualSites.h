/*
 * Bodies that hold virtual sites (four- and five-site water). OpenMM hands a site's force to its
 * parents before an integrator sees it; a body holding both must count that force once. Checked
 * against exact answers: the momentum a constant force on the site alone imparts, energy
 * conservation without friction (error quartering as the step halves, no drift), and the body's
 * shape obeying the System's constraints and site definitions exactly although the positions it was
 * built from were rounded.
 */
#include "RigidBodyTestUtilities.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/VirtualSite.h"
#include <gtest/gtest.h>
#include <random>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

const double OH = 0.09572, HH = 0.15139;  // nm: TIP4P-Ew and TIP5P geometry (HOH 104.52 degrees)

/** Water with virtual sites: TIP4P-Ew (one ThreeParticleAverageSite) or TIP5P (two OutOfPlaneSites). */
struct WaterModel {
    int numSites;
    double oxygenSigma, oxygenEpsilon, hydrogenCharge;
};

const WaterModel TIP4PEw = {1, 0.316435, 0.680946, 0.52422};
const WaterModel TIP5P = {2, 0.312, 0.66944, 0.241};

/** Adds one water's particles, sites, constraints and nonbonded parameters; returns its particles. */
std::vector<int> addWater(System& system, NonbondedForce& nonbonded, const WaterModel& model) {
    int o = system.addParticle(15.99943), h1 = system.addParticle(1.007947), h2 = system.addParticle(1.007947);
    std::vector<int> particles = {o, h1, h2};
    nonbonded.addParticle(0, model.oxygenSigma, model.oxygenEpsilon);
    nonbonded.addParticle(model.hydrogenCharge, 1, 0);
    nonbonded.addParticle(model.hydrogenCharge, 1, 0);
    if (model.numSites == 1) {
        int m = system.addParticle(0);
        system.setVirtualSite(m, new ThreeParticleAverageSite(o, h1, h2, 0.786646558, 0.106676721, 0.106676721));
        nonbonded.addParticle(-2*model.hydrogenCharge, 1, 0);
        particles.push_back(m);
    }
    else
        for (double cross : {6.4437903, -6.4437903}) {
            int lp = system.addParticle(0);
            system.setVirtualSite(lp, new OutOfPlaneSite(o, h1, h2, -0.34490826, -0.34490826, cross));
            nonbonded.addParticle(-model.hydrogenCharge, 1, 0);
            particles.push_back(lp);
        }
    system.addConstraint(o, h1, OH);
    system.addConstraint(o, h2, OH);
    system.addConstraint(h1, h2, HH);
    for (int i = 0; i < (int) particles.size(); i++)
        for (int j = i+1; j < (int) particles.size(); j++)
            nonbonded.addException(particles[i], particles[j], 0, 1, 0);
    return particles;
}

/** A cluster of waters on a cubic lattice, randomly oriented, positions rounded to 1e-4 nm as in a PDB file. */
struct WaterCluster {
    System system;
    std::vector<std::vector<int> > molecules;
    std::vector<Vec3> positions;
    WaterCluster(const WaterModel& model, int perSide, double spacing) {
        NonbondedForce* nonbonded = new NonbondedForce();
        nonbonded->setNonbondedMethod(NonbondedForce::NoCutoff);
        system.addForce(nonbonded);
        std::mt19937 rng(5);
        std::normal_distribution<double> normal;
        double angle = 104.52*M_PI/180;
        for (int i = 0; i < perSide; i++)
            for (int j = 0; j < perSide; j++)
                for (int k = 0; k < perSide; k++) {
                    molecules.push_back(addWater(system, *nonbonded, model));
                    Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
                    Eigen::Matrix3d r = q.normalized().toRotationMatrix();
                    Eigen::Vector3d centre(i*spacing, j*spacing, k*spacing);
                    std::vector<Eigen::Vector3d> local = {Eigen::Vector3d::Zero(), Eigen::Vector3d(OH, 0, 0),
                                                          Eigen::Vector3d(OH*std::cos(angle), OH*std::sin(angle), 0)};
                    for (const Eigen::Vector3d& p : local)
                        positions.push_back(toVec3(centre+r*p));
                    for (int s = 0; s < model.numSites; s++)
                        positions.push_back(positions[positions.size()-3]);  // computed from the parents below
                }
        for (Vec3& p : positions)
            for (int d = 0; d < 3; d++)
                p[d] = 1e-4*std::round(p[d]/1e-4);
    }
    void addBodies(RigidLangevinIntegrator& integrator) const {
        for (const std::vector<int>& m : molecules) {
            integrator.addRigidBody(m);
            for (int i = 0; i < 3; i++)
                integrator.setParticleRadius(m[i], 0.15);
        }
    }
};

/** The site positions their definitions give for the parents' positions. */
std::vector<Vec3> sitePositions(const System& system, const std::vector<Vec3>& positions) {
    std::vector<Vec3> result = positions;
    for (int p = 0; p < system.getNumParticles(); p++) {
        if (!system.isVirtualSite(p))
            continue;
        const VirtualSite& site = system.getVirtualSite(p);
        Vec3 r1 = positions[site.getParticle(0)], r2 = positions[site.getParticle(1)], r3 = positions[site.getParticle(2)];
        if (auto s = dynamic_cast<const ThreeParticleAverageSite*>(&site))
            result[p] = r1*s->getWeight(0)+r2*s->getWeight(1)+r3*s->getWeight(2);
        else if (auto s = dynamic_cast<const OutOfPlaneSite*>(&site)) {
            Vec3 d12 = r2-r1, d13 = r3-r1;
            result[p] = r1+d12*s->getWeight12()+d13*s->getWeight13()+d12.cross(d13)*s->getWeightCross();
        }
    }
    return result;
}

double distance(const Vec3& a, const Vec3& b) {
    return std::sqrt((a-b).dot(a-b));
}

} // namespace

class VirtualSites : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(VirtualSites, ConstantForceOnASiteImpartsItsMomentumOnce) {
    // A constant force F on the site alone: OpenMM hands it to the parents, and the body's momentum
    // grows by exactly F per unit time. Counting the site's own entry as well would double it.
    for (const WaterModel& model : {TIP4PEw, TIP5P}) {
        WaterCluster cluster(model, 1, 0);
        cluster.system.removeForce(0);
        Vec3 f(3, -2, 1);  // kJ/(mol nm)
        CustomExternalForce* pull = new CustomExternalForce("-3*x+2*y-z");
        pull->addParticle(cluster.molecules[0][3]);
        cluster.system.addForce(pull);
        double h = 0.001;
        RigidLangevinIntegrator integrator(0, 0, h);
        cluster.addBodies(integrator);
        std::unique_ptr<Context> context(createContext(cluster.system, integrator, GetParam()));
        context->setPositions(cluster.positions);
        auto momentum = [&] () {
            std::vector<Vec3> v = context->getState(State::Velocities).getVelocities();
            Vec3 p;
            for (int i = 0; i < cluster.system.getNumParticles(); i++)
                p += v[i]*cluster.system.getParticleMass(i);
            return p;
        };
        integrator.step(10);
        Vec3 before = momentum();
        integrator.step(100);
        Vec3 gained = momentum()-before;
        double tolerance = (GetParam().precision == "double" ? 1e-9 : 1e-4);
        for (int k = 0; k < 3; k++)
            EXPECT_NEAR(f[k]*100*h, gained[k], tolerance*std::sqrt(f.dot(f))*100*h) << model.numSites << " sites, component " << k;
    }
}

TEST_P(VirtualSites, WaterWithSitesConservesEnergy) {
    // Interacting rigid waters without friction. Velocity Verlet's energy error is O(h^2): started
    // from the same state, 0.1 ps at 2 fs strays from the starting energy 4 times as far (rms) as at
    // 1 fs, for the two trajectories stay together that long. Windows start from states 0.4 ps apart
    // along a 1 fs run, which itself must not drift. A site force counted twice is not the gradient of
    // the energy: its error does not scale as h^2 (the ratio falls toward 1) and the energy drifts.
    // (Comparing two independent runs instead lets their chaotic trajectories scatter the ratio.)
    for (const WaterModel& model : {TIP4PEw, TIP5P}) {
        WaterCluster cluster(model, 2, 0.31);
        const double h = 0.001;
        RigidLangevinIntegrator integrator(300, 0, h);
        cluster.addBodies(integrator);
        std::unique_ptr<Context> context(createContext(cluster.system, integrator, GetParam()));
        context->setPositions(cluster.positions);
        context->setVelocitiesToTemperature(300, 11);
        auto energy = [&] () {
            State s = context->getState(State::Energy);
            return s.getKineticEnergy()+s.getPotentialEnergy();
        };
        const int windows = 8, samples = 10;  // windows of 0.1 ps sampled every 10 fs
        double squared[2] = {0, 0};
        std::vector<double> ratios, trace;
        for (int w = 0; w < windows; w++) {
            State start = context->getState(State::Positions | State::Velocities);
            double window[2] = {0, 0};
            for (int run = 0; run < 2; run++) {
                double step = (run == 0 ? 2*h : h);
                integrator.setStepSize(step);
                context->setState(start);
                double initial = energy();
                for (int i = 0; i < samples; i++) {
                    integrator.step((int) std::round(0.01/step));
                    window[run] += std::pow(energy()-initial, 2)/samples;
                }
                squared[run] += window[run]/windows;
            }
            ratios.push_back(std::sqrt(window[0]/window[1]));
            integrator.setStepSize(h);
            context->setState(start);
            for (int i = 0; i < 80; i++) {
                integrator.step(5);
                trace.push_back(energy());
            }
        }
        double ratio = std::sqrt(squared[0]/squared[1]), mean = 0, spread = 0, sum = 0, square = 0, first = 0, last = 0;
        for (double r : ratios)
            mean += r/windows;
        for (double r : ratios)
            spread += (r-mean)*(r-mean)/(windows-1);
        int n = trace.size();
        for (int i = 0; i < n; i++) {
            sum += trace[i]/n;
            square += trace[i]*trace[i]/n;
            first += (i < n/4 ? trace[i]/(n/4) : 0);
            last += (i >= 3*n/4 ? trace[i]/(n/4) : 0);
        }
        double deviation = std::sqrt(std::max(0.0, square-sum*sum));
        std::cout << GetParam().name() << ", " << 3+model.numSites << "-site water: rms energy error over 0.1 ps at 2 fs / 1 fs "
                  << ratio << " (windows: mean " << mean << ", sd " << std::sqrt(spread) << "); 1 fs run: deviation " << deviation
                  << " kJ/mol, drift over 3.2 ps " << last-first << std::endl;
        // Four standard errors of the windows' mean ratio (each window's ratio scatters by 0.1-0.2),
        // and 0.05 for the O(h^2) part of the ratio itself; a doubled site force gives about 1.
        EXPECT_NEAR(4.0, mean, 4*std::sqrt(spread/windows)+0.05);
        // Verlet's energy error is h^2 times a function of the configuration, so the run's first and
        // last quarters differ by a fraction of its rms as the cluster rearranges (0.3-0.85 of it on
        // Reference, CPU and OpenCL); a doubled site force drifts by tens of kJ/mol, a thousand times more.
        EXPECT_LT(std::abs(last-first), 2*deviation);
    }
}

TEST_P(VirtualSites, ShapeObeysConstraintsAndSiteDefinitions) {
    // Positions rounded to 1e-4 nm; the bodies take the exact distances the constraints fix and put
    // their sites where OpenMM's definitions put them, so both placements agree to round-off.
    for (const WaterModel& model : {TIP4PEw, TIP5P}) {
        WaterCluster cluster(model, 2, 0.31);
        RigidLangevinIntegrator integrator(300, 0, 0.001);
        cluster.addBodies(integrator);
        std::unique_ptr<Context> context(createContext(cluster.system, integrator, GetParam()));
        context->setPositions(cluster.positions);
        context->setVelocitiesToTemperature(300, 3);
        integrator.step(20);
        std::vector<Vec3> pos = context->getState(State::Positions).getPositions();
        std::vector<Vec3> fromParents = sitePositions(cluster.system, pos);
        // OpenMM's SETTLE, which makes the shapes, holds water's distances to a relative 8e-9 (its
        // own fixed point); the rounding of the input is 1e-4 nm.
        double tolerance = (GetParam().precision == "double" ? 1e-8 : 1e-5);
        double worstDistance = 0, worstSite = 0;
        for (const std::vector<int>& m : cluster.molecules) {
            worstDistance = std::max(worstDistance, std::abs(distance(pos[m[0]], pos[m[1]])-OH)/OH);
            worstDistance = std::max(worstDistance, std::abs(distance(pos[m[0]], pos[m[2]])-OH)/OH);
            worstDistance = std::max(worstDistance, std::abs(distance(pos[m[1]], pos[m[2]])-HH)/HH);
            for (int s = 3; s < (int) m.size(); s++)
                worstSite = std::max(worstSite, distance(pos[m[s]], fromParents[m[s]]));
        }
        std::cout << GetParam().name() << ", " << 3+model.numSites << "-site water: relative constraint error " << worstDistance << ", site error "
                  << worstSite << " nm" << std::endl;
        EXPECT_LT(worstDistance, tolerance);
        EXPECT_LT(worstSite, (GetParam().precision == "double" ? 1e-12 : 1e-5));
        // The rounded input alone is off by far more: the test sees the difference.
        double inputError = std::abs(distance(cluster.positions[0], cluster.positions[1])-OH)/OH+std::abs(distance(cluster.positions[1], cluster.positions[2])-HH)/HH;
        EXPECT_GT(inputError, 100*tolerance);
    }
}

TEST_P(VirtualSites, SiteWithAParentOutsideItsBodyIsAnError) {
    WaterCluster cluster(TIP4PEw, 1, 0);
    RigidLangevinIntegrator integrator(300, 0, 0.001);
    const std::vector<int>& m = cluster.molecules[0];
    integrator.addRigidBody({m[0], m[1], m[3]});  // the second hydrogen, a parent of the site, is left out
    for (int i = 0; i < 3; i++)
        integrator.setParticleRadius(m[i], 0.15);
    cluster.system.removeConstraint(2);
    cluster.system.removeConstraint(1);
    try {
        std::unique_ptr<Context> context(createContext(cluster.system, integrator, GetParam()));
        FAIL() << "a body holding a virtual site without one of its parents was accepted";
    }
    catch (const OpenMMException& e) {
        std::string message = e.what();
        EXPECT_NE(std::string::npos, message.find("particle 3 in rigid body 0 is a virtual site whose parent particle 2 is in no rigid body")) << message;
    }
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, VirtualSites, testing::ValuesIn(platformConfigs()), PlatformConfigName());
