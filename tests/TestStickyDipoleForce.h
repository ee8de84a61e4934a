/*
 * StickyDipoleForce: the energy against a direct sum written here from the published form (body
 * frames built another way, the sticky terms from polar angles), for every SSD-family model, with
 * and without a periodic cutoff, switching and reaction field; forces on every particle (sites and
 * reference particles) against a five-point finite difference of the energy; torques on rigid
 * molecules against the energy's derivative under rotation; invariance under a rigid rotation of
 * the whole system; energy conservation of rigid waters; XmlSerializer round trips; clear errors
 * for bad sites.
 */
#include "RigidBodyTestUtilities.h"
#include "StickyDipoleForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/serialization/XmlSerializer.h"
#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <functional>
#include <random>
#include <sstream>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

/** Waters as three particles: the site (at the oxygen) and two hydrogens (O-H 0.09572 nm, 104.52 degrees). */
struct WaterBox {
    System system;
    StickyDipoleForce* force;
    std::vector<Vec3> positions;
    Vec3 box;
};

WaterBox makeWaters(const std::string& model, int perSide, double spacing, unsigned seed) {
    WaterBox w;
    w.force = new StickyDipoleForce();
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(-1, 1);
    double side = perSide*spacing;
    w.box = Vec3(side, side, side);
    w.system.setDefaultPeriodicBoxVectors(Vec3(side, 0, 0), Vec3(0, side, 0), Vec3(0, 0, side));
    double angle = 104.52*M_PI/180, oh = 0.09572;
    Eigen::Vector3d h1(0, oh*std::sin(angle/2), oh*std::cos(angle/2)), h2(0, -h1[1], h1[2]);
    StickyDipoleForce::SiteParameters parameters = StickyDipoleForce::getModelParameters(model);
    for (int i = 0; i < perSide; i++)
        for (int j = 0; j < perSide; j++)
            for (int k = 0; k < perSide; k++) {
                Eigen::Vector3d center = Eigen::Vector3d(i+0.5, j+0.5, k+0.5)*spacing+Eigen::Vector3d(uniform(random), uniform(random), uniform(random))*0.03*spacing;
                Eigen::Matrix3d rotation = Eigen::Quaterniond(Eigen::Vector4d(uniform(random), uniform(random), uniform(random), uniform(random)).normalized()).toRotationMatrix();
                int site = w.system.addParticle(15.9994);
                w.system.addParticle(1.008);
                w.system.addParticle(1.008);
                w.positions.push_back(toVec3(center));
                w.positions.push_back(toVec3(center+rotation*h1));
                w.positions.push_back(toVec3(center+rotation*h2));
                w.force->addSite(site, site+1, site+2, parameters);
            }
    w.system.addForce(w.force);
    return w;
}

/** The axes of a water's body frame: z along the bisector towards the hydrogens, x normal to the plane. */
void waterFrame(const Vec3& o, const Vec3& h1, const Vec3& h2, Vec3& x, Vec3& y, Vec3& z) {
    z = (h1-o)+(h2-o);
    z /= std::sqrt(z.dot(z));
    x = (h1-o).cross(h2-o);
    x /= std::sqrt(x.dot(x));
    y = z.cross(x);
}

double cubic(double r, double lower, double upper) {
    if (r < lower)
        return 1;
    if (r >= upper)
        return 0;
    return (upper-r)*(upper-r)*(upper+2*r-3*lower)/std::pow(upper-lower, 3);
}

/** One molecule's half of the sticky energy, from the polar angles of the other molecule in its frame. */
double stickyHalf(const StickyDipoleForce::SiteParameters& p, const Vec3& x, const Vec3& y, const Vec3& z, const Vec3& toOther) {
    double r = std::sqrt(toOther.dot(toOther));
    double theta = std::acos(z.dot(toOther)/r), phi = std::atan2(y.dot(toOther), x.dot(toOther));
    double w = std::sin(theta)*std::sin(2*theta)*std::cos(2*phi);
    double wPrime = std::pow(std::cos(theta)-0.6, 2)*std::pow(std::cos(theta)+0.8, 2)-p.w0;
    return 0.5*(p.nu0*cubic(r, p.rL, p.rU)*w+p.nu0Prime*cubic(r, p.rLPrime, p.rUPrime)*wPrime);
}

/**
 * The energy of the force, summed here over all pairs from the published form; also the sticky
 * part of it and the number of pairs in the switching region, to show that the case tests them.
 */
double directSum(const WaterBox& w, const std::vector<Vec3>& positions, double& stickyEnergy, int& switchedPairs) {
    const StickyDipoleForce& f = *w.force;
    // 1/(4 pi eps0) in kJ nm/(mol e^2), from CODATA 2018: e^2 N_A/(4 pi eps0), J m/mol -> kJ nm/mol.
    const double k = 1.602176634e-19*1.602176634e-19*6.02214076e23/(4*M_PI*8.8541878128e-12)*1e-3*1e9;
    bool cutoff = f.getNonbondedMethod() != StickyDipoleForce::NoCutoff, periodic = f.usesPeriodicBoundaryConditions();
    double rc = f.getCutoffDistance();
    double kappa = cutoff ? (f.getReactionFieldDielectric()-1)/((2*f.getReactionFieldDielectric()+1)*rc*rc*rc) : 0;
    std::set<std::pair<int, int> > excluded;
    for (int e = 0; e < f.getNumExclusions(); e++) {
        int a, b;
        f.getExclusionSites(e, a, b);
        excluded.insert(std::make_pair(std::min(a, b), std::max(a, b)));
    }
    double energy = 0;
    stickyEnergy = 0;
    switchedPairs = 0;
    for (int i = 0; i < f.getNumSites(); i++) {
        int pi, ai, bi;
        StickyDipoleForce::SiteParameters qi;
        f.getSiteParameters(i, pi, ai, bi, qi);
        if (cutoff)
            energy -= k*kappa*qi.dipole*qi.dipole;
        for (int j = i+1; j < f.getNumSites(); j++) {
            if (excluded.count(std::make_pair(i, j)))
                continue;
            int pj, aj, bj;
            StickyDipoleForce::SiteParameters qj;
            f.getSiteParameters(j, pj, aj, bj, qj);
            Vec3 d = positions[pj]-positions[pi];
            if (periodic)
                for (int c = 0; c < 3; c++)
                    d[c] -= w.box[c]*std::round(d[c]/w.box[c]);
            double r = std::sqrt(d.dot(d));
            if (cutoff && r >= rc)
                continue;
            Vec3 xi, yi, zi, xj, yj, zj;
            waterFrame(positions[pi], positions[ai], positions[bi], xi, yi, zi);
            waterFrame(positions[pj], positions[aj], positions[bj], xj, yj, zj);
            double sigma = 0.5*(qi.sigma+qj.sigma), epsilon = std::sqrt(qi.epsilon*qj.epsilon);
            double lj = 4*epsilon*(std::pow(sigma/r, 12)-std::pow(sigma/r, 6));
            Vec3 mi = zi*qi.dipole, mj = zj*qj.dipole, n = d/r;
            double dipole = k*((mi.dot(mj)-3*mi.dot(n)*mj.dot(n))/(r*r*r)-2*kappa*mi.dot(mj));
            double s = (cutoff && f.getUseSwitchingFunction()) ? cubic(r, f.getSwitchingDistance(), rc) : 1.0;
            double sticky = stickyHalf(qi, xi, yi, zi, d)+stickyHalf(qj, xj, yj, zj, -d);
            energy += s*(lj+dipole)+sticky;
            stickyEnergy += sticky;
            switchedPairs += (s < 1);
        }
    }
    return energy;
}

void usePeriodicCutoff(WaterBox& w) {
    w.force->setNonbondedMethod(StickyDipoleForce::CutoffPeriodic);
    w.force->setCutoffDistance(0.55);
    w.force->setUseSwitchingFunction(true);
    w.force->setSwitchingDistance(0.45);
}

double energyOf(Context& context, const std::vector<Vec3>& positions) {
    context.setPositions(positions);
    return context.getState(State::Energy).getPotentialEnergy();
}

/** dU/ds at s = 0 by the five-point stencil (error of order h^4), positionsAt(s) the displaced configuration. */
double energyDerivative(Context& context, const std::function<std::vector<Vec3>(double)>& positionsAt) {
    const double h = 1e-4;
    double e[4];
    const double steps[4] = {-2, -1, 1, 2};
    for (int s = 0; s < 4; s++)
        e[s] = energyOf(context, positionsAt(steps[s]*h));
    return (e[0]-8*e[1]+8*e[2]-e[3])/(12*h);
}

} // namespace

class StickyDipoleForceTest : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(StickyDipoleForceTest, EnergyIsTheDirectSumForEveryModel) {
    for (const std::string model : {"SSD", "SSD1", "SSD/E", "SSD/RF"})
        for (bool withCutoff : {false, true}) {
            SCOPED_TRACE(model+(withCutoff ? ", periodic cutoff with switching and reaction field" : ", no cutoff"));
            WaterBox w = makeWaters(model, 4, 0.3, 11);
            w.force->addExclusion(0, 1);
            w.force->addExclusion(5, 2);
            if (withCutoff)
                usePeriodicCutoff(w);
            VerletIntegrator integrator(0.001);
            std::unique_ptr<Context> context(createContext(w.system, integrator, GetParam()));
            double sticky;
            int switched;
            double expected = directSum(w, w.positions, sticky, switched), energy = energyOf(*context, w.positions);
            std::cout << model << (withCutoff ? " cutoff" : " no cutoff") << ": " << energy << " kJ/mol for 64 waters, sticky part "
                      << sticky << ", " << switched << " pairs switched" << std::endl;
            EXPECT_NEAR(expected, energy, 1e-10*std::abs(expected));
            // The configuration exercises every term: pairs within the sticky range, and (with a
            // cutoff) pairs in the switching region.
            EXPECT_GT(std::abs(sticky), 10.0);
            if (withCutoff) {
                EXPECT_GT(switched, 100);
            }
        }
}

TEST_P(StickyDipoleForceTest, ForcesAreTheGradientOfTheEnergy) {
    for (bool withCutoff : {false, true}) {
        SCOPED_TRACE(withCutoff ? "periodic cutoff" : "no cutoff");
        WaterBox w = makeWaters("SSD/RF", 3, 0.3, 5);
        if (withCutoff) {
            usePeriodicCutoff(w);
            w.force->setCutoffDistance(0.44);
            w.force->setSwitchingDistance(0.36);
        }
        VerletIntegrator integrator(0.001);
        std::unique_ptr<Context> context(createContext(w.system, integrator, GetParam()));
        context->setPositions(w.positions);
        std::vector<Vec3> forces = context->getState(State::Forces).getForces();
        double largest = 0;
        for (const Vec3& f : forces)
            largest = std::max(largest, std::sqrt(f.dot(f)));
        double worst = 0;
        for (int p = 0; p < (int) w.positions.size(); p++)
            for (int c = 0; c < 3; c++) {
                double derivative = energyDerivative(*context, [&](double s) {
                    std::vector<Vec3> moved = w.positions;
                    moved[p][c] += s;
                    return moved;
                });
                worst = std::max(worst, std::abs(-derivative-forces[p][c]));
            }
        std::cout << "largest force " << largest << " kJ/mol/nm, largest difference from -dU/dx " << worst << std::endl;
        EXPECT_LT(worst, 1e-6*largest);
    }
}

TEST_P(StickyDipoleForceTest, TorquesAreTheDerivativeUnderRotation) {
    WaterBox w = makeWaters("SSD", 3, 0.3, 9);
    VerletIntegrator integrator(0.001);
    std::unique_ptr<Context> context(createContext(w.system, integrator, GetParam()));
    context->setPositions(w.positions);
    std::vector<Vec3> forces = context->getState(State::Forces).getForces();
    double worst = 0, largest = 0;
    for (int molecule = 0; molecule < 27; molecule += 4) {
        int o = 3*molecule;
        Vec3 torque;
        for (int p = o; p < o+3; p++)
            torque += (w.positions[p]-w.positions[o]).cross(forces[p]);
        for (int axis = 0; axis < 3; axis++) {
            // dU/dalpha for a rotation of the molecule about the axis through its site: -torque[axis].
            double derivative = energyDerivative(*context, [&](double angle) {
                Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
                std::vector<Vec3> moved = w.positions;
                for (int p = o+1; p < o+3; p++)
                    moved[p] = w.positions[o]+toVec3(rotation*toEigen(w.positions[p]-w.positions[o]));
                return moved;
            });
            worst = std::max(worst, std::abs(-derivative-torque[axis]));
            largest = std::max(largest, std::abs(torque[axis]));
        }
    }
    std::cout << "largest torque " << largest << " kJ/mol, largest difference from -dU/dalpha " << worst << std::endl;
    EXPECT_GT(largest, 1.0);
    EXPECT_LT(worst, 1e-6*largest);
}

TEST_P(StickyDipoleForceTest, RotatingTheWholeSystemChangesNothing) {
    WaterBox w = makeWaters("SSD/E", 3, 0.3, 3);
    VerletIntegrator integrator(0.001);
    std::unique_ptr<Context> context(createContext(w.system, integrator, GetParam()));
    context->setPositions(w.positions);
    State before = context->getState(State::Energy | State::Forces);
    Eigen::Matrix3d rotation = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
    std::vector<Vec3> rotated;
    for (const Vec3& p : w.positions)
        rotated.push_back(toVec3(rotation*toEigen(p)));
    context->setPositions(rotated);
    State after = context->getState(State::Energy | State::Forces);
    EXPECT_NEAR(before.getPotentialEnergy(), after.getPotentialEnergy(), 1e-10*std::abs(before.getPotentialEnergy()));
    double worst = 0, largest = 0;
    for (int p = 0; p < (int) rotated.size(); p++) {
        Vec3 expected = toVec3(rotation*toEigen(before.getForces()[p]));
        Vec3 difference = after.getForces()[p]-expected;
        worst = std::max(worst, std::sqrt(difference.dot(difference)));
        largest = std::max(largest, std::sqrt(expected.dot(expected)));
    }
    EXPECT_LT(worst, 1e-10*largest);
}

TEST_P(StickyDipoleForceTest, BadSitesAreClearErrors) {
    const PlatformConfig& config = GetParam();
    auto expectError = [&](WaterBox& w, const std::vector<std::string>& fragments) {
        VerletIntegrator integrator(0.001);
        try {
            Context context(w.system, integrator, config.get(), config.properties());
            ADD_FAILURE() << "expected an OpenMMException mentioning '" << fragments[0] << "'";
        }
        catch (const OpenMMException& e) {
            for (const std::string& fragment : fragments)
                EXPECT_NE(std::string::npos, std::string(e.what()).find(fragment)) << e.what();
        }
    };
    StickyDipoleForce::SiteParameters p = StickyDipoleForce::getModelParameters("SSD");
    {
        WaterBox w = makeWaters("SSD", 2, 0.3, 1);
        w.force->setSiteParameters(3, 9, 9, 11, p);
        expectError(w, {"site 3", "three different particles"});
    }
    {
        WaterBox w = makeWaters("SSD", 2, 0.3, 1);
        w.force->setSiteParameters(2, 6, 7, 99, p);
        expectError(w, {"site 2", "particle 99"});
    }
    {
        WaterBox w = makeWaters("SSD", 2, 0.3, 1);
        usePeriodicCutoff(w);
        expectError(w, {"cutoff", "half the periodic box"});
    }
    {
        WaterBox w = makeWaters("SSD", 2, 0.3, 1);
        StickyDipoleForce::SiteParameters bad = p;
        bad.rU = bad.rL;
        w.force->setSiteParameters(1, 3, 4, 5, bad);
        expectError(w, {"site 1", "rL < rU"});
    }
    EXPECT_THROW(StickyDipoleForce::getModelParameters("TIP3P"), OpenMMException);
    {
        // Without a sticky term its switch may be empty: Lennard-Jones and dipole sites alone.
        WaterBox w = makeWaters("SSD", 2, 0.3, 1);
        StickyDipoleForce::SiteParameters plain = p;
        plain.nu0 = plain.nu0Prime = 0;
        plain.rL = plain.rU = plain.rLPrime = plain.rUPrime = 0;
        for (int i = 0; i < 8; i++)
            w.force->setSiteParameters(i, 3*i, 3*i+1, 3*i+2, plain);
        VerletIntegrator integrator(0.001);
        std::unique_ptr<Context> context(createContext(w.system, integrator, config));
        context->setPositions(w.positions);
        EXPECT_TRUE(std::isfinite(context->getState(State::Energy).getPotentialEnergy()));
    }
    {
        // A box shrunk below twice the cutoff after the Context was made is caught when the energy is computed.
        WaterBox w = makeWaters("SSD", 4, 0.3, 1);
        usePeriodicCutoff(w);
        VerletIntegrator integrator(0.001);
        std::unique_ptr<Context> context(createContext(w.system, integrator, config));
        context->setPositions(w.positions);
        context->setPeriodicBoxVectors(Vec3(1.0, 0, 0), Vec3(0, 1.0, 0), Vec3(0, 0, 1.0));
        try {
            context->getState(State::Energy);
            ADD_FAILURE() << "expected an OpenMMException about the box";
        }
        catch (const OpenMMException& e) {
            // The GPU platforms' neighbour list (OpenMM's) says so before this force is reached.
            std::string message = e.what();
            EXPECT_TRUE(message.find("half the periodic box") != std::string::npos || message.find("twice the nonbonded cutoff") != std::string::npos) << message;
        }
    }
}

TEST_P(StickyDipoleForceTest, RigidWatersConserveEnergyWithoutFriction) {
    // 27 SSD/RF waters as this plugin's bodies, periodic cutoff with switching and reaction field,
    // no friction: the energy error of a second order integrator falls fourfold with each halving
    // of the step, and does not drift beyond its fluctuation. One 2 ps run is one chaotic
    // realization: over 16 velocity seeds its ratio of fluctuations scattered by 0.36 about 4
    // (3.3 to 4.9), and its drift over the run reached 1.15 times the fluctuation, so a change at
    // rounding could fail a single run. Both are judged on the mean of Seeds runs, against its standard error.
    const int Seeds = 8, Samples = 200;
    const double steps[2] = {0.001, 0.0005};
    std::vector<double> ratio, drift[2], deviation[2];
    for (int seed = 1; seed <= Seeds; seed++) {
        for (int k = 0; k < 2; k++) {
            WaterBox w = makeWaters("SSD/RF", 3, 0.31, 2);
            usePeriodicCutoff(w);
            w.force->setCutoffDistance(0.45);
            w.force->setSwitchingDistance(0.38);
            RigidLangevinIntegrator integrator(300, 0, steps[k]);
            for (int m = 0; m < 27; m++) {
                integrator.addRigidBody({3*m, 3*m+1, 3*m+2});
                for (int p = 3*m; p < 3*m+3; p++)
                    integrator.setParticleRadius(p, 0.15);
            }
            std::unique_ptr<Context> context(createContext(w.system, integrator, GetParam()));
            context->setPositions(w.positions);
            context->setVelocitiesToTemperature(300, seed);
            // 2 ps, sampled every 10 fs.
            int every = (int) std::round(0.01/steps[k]);
            std::vector<double> energy = sampleTotalEnergy(*context, integrator, every, Samples);
            double mean = 0, square = 0, slope = 0, times = 0;
            for (double e : energy)
                mean += e/Samples;
            for (int i = 0; i < Samples; i++) {
                double t = (i-0.5*(Samples-1))*0.01;
                square += (energy[i]-mean)*(energy[i]-mean)/Samples;
                slope += t*(energy[i]-mean);
                times += t*t;
            }
            deviation[k].push_back(std::sqrt(square));
            drift[k].push_back(slope/times);  // kJ/mol per ps
        }
        ratio.push_back(deviation[0].back()/deviation[1].back());
    }
    auto meanAndError = [] (const std::vector<double>& x) {
        double mean = 0, square = 0;
        for (double v : x)
            mean += v/x.size();
        for (double v : x)
            square += (v-mean)*(v-mean)/(x.size()-1);
        return std::make_pair(mean, std::sqrt(square/x.size()));
    };
    for (int k = 0; k < 2; k++) {
        std::pair<double, double> dev = meanAndError(deviation[k]), slope = meanAndError(drift[k]);
        std::cout << "step " << steps[k]*1000 << " fs: energy deviation " << dev.first << " +- " << dev.second << " kJ/mol, drift "
                  << slope.first*1000/27 << " +- " << slope.second*1000/27 << " kJ/mol/ns per molecule (" << Seeds << " seeds)" << std::endl;
        // No drift beyond the fluctuation over the run: 2 ps times the mean drift within the mean
        // deviation (over the 16 seeds, five standard errors of the mean drift of 8).
        EXPECT_LT(std::abs(slope.first)*2.0, dev.first);
    }
    // Second order: 4 within five standard errors (about 0.6; a first order integrator gives 2).
    std::pair<double, double> r = meanAndError(ratio);
    std::cout << "ratio of deviations " << r.first << " +- " << r.second << std::endl;
    EXPECT_NEAR(4.0, r.first, 5*r.second);
}

TEST_P(StickyDipoleForceTest, XmlRoundTripKeepsEverything) {
    WaterBox w = makeWaters("SSD/E", 3, 0.3, 4);
    usePeriodicCutoff(w);
    w.force->setCutoffDistance(0.44);
    w.force->setSwitchingDistance(0.37);
    w.force->setReactionFieldDielectric(78.5);
    w.force->addExclusion(3, 4);
    w.force->setForceGroup(3);
    w.force->setName("ssd");
    StickyDipoleForce::SiteParameters odd = StickyDipoleForce::getModelParameters("SSD");
    odd.w0 = 0.05;
    w.force->setSiteParameters(7, 21, 23, 22, odd);
    std::stringstream buffer;
    XmlSerializer::serialize<System>(&w.system, "System", buffer);
    std::unique_ptr<System> copy(XmlSerializer::deserialize<System>(buffer));
    const StickyDipoleForce& read = dynamic_cast<const StickyDipoleForce&>(copy->getForce(0));
    EXPECT_EQ(w.force->getNonbondedMethod(), read.getNonbondedMethod());
    EXPECT_EQ(w.force->getCutoffDistance(), read.getCutoffDistance());
    EXPECT_EQ(w.force->getUseSwitchingFunction(), read.getUseSwitchingFunction());
    EXPECT_EQ(w.force->getSwitchingDistance(), read.getSwitchingDistance());
    EXPECT_EQ(w.force->getReactionFieldDielectric(), read.getReactionFieldDielectric());
    EXPECT_EQ(3, read.getForceGroup());
    EXPECT_EQ("ssd", read.getName());
    ASSERT_EQ(w.force->getNumSites(), read.getNumSites());
    ASSERT_EQ(w.force->getNumExclusions(), read.getNumExclusions());
    for (int i = 0; i < read.getNumSites(); i++) {
        int a[3], b[3];
        StickyDipoleForce::SiteParameters p, q;
        w.force->getSiteParameters(i, a[0], a[1], a[2], p);
        read.getSiteParameters(i, b[0], b[1], b[2], q);
        for (int k = 0; k < 3; k++)
            EXPECT_EQ(a[k], b[k]);
        const double pv[] = {p.sigma, p.epsilon, p.dipole, p.nu0, p.rL, p.rU, p.nu0Prime, p.rLPrime, p.rUPrime, p.w0};
        const double qv[] = {q.sigma, q.epsilon, q.dipole, q.nu0, q.rL, q.rU, q.nu0Prime, q.rLPrime, q.rUPrime, q.w0};
        for (int k = 0; k < 10; k++)
            EXPECT_EQ(pv[k], qv[k]) << "site " << i << ", parameter " << k;
    }
    int s1, s2;
    read.getExclusionSites(0, s1, s2);
    EXPECT_EQ(3, s1);
    EXPECT_EQ(4, s2);
    // The same energy from the copy (forces in group 3 only).
    VerletIntegrator i1(0.001), i2(0.001);
    std::unique_ptr<Context> original(createContext(w.system, i1, GetParam())), restored(createContext(*copy, i2, GetParam()));
    EXPECT_EQ(energyOf(*original, w.positions), energyOf(*restored, w.positions));
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, StickyDipoleForceTest, testing::ValuesIn(platformConfigs()), PlatformConfigName());

class StickyDipoleForceParity : public testing::TestWithParam<PlatformConfig> {
};

/**
 * The platform's energy and forces against Reference's, in each precision, for 64 waters of two
 * site types in a periodic box with switching, reaction field and exclusions.
 *
 * Tolerances. In double precision the platforms differ from Reference by round-off and, on GPU
 * platforms, by OpenMM's 64-bit fixed-point force accumulation (2^-32 kJ/mol/nm per added term, a
 * few hundred terms per particle): 1e-9 of the largest force, 1e-10 of the energy. In single and
 * mixed precision positions and pair terms are rounded to 6e-8 relative; a pair's forces near
 * contact come from r^-13 and r^-4 terms whose rounding grows about 13-fold, and a particle's force
 * cancels among ~100 pairs of ~10^3 kJ/mol/nm: 1e-5 of the largest force, and 1e-6 of the energy
 * (measured on PoCL: 3e-6 and 1e-7). A wrong term (a sign, a missing switch or sticky term, a pair
 * counted twice) changes them by more than 1e-2.
 */
TEST_P(StickyDipoleForceParity, AgreesWithReference) {
    WaterBox w = makeWaters("SSD/RF", 4, 0.3, 13);
    usePeriodicCutoff(w);
    w.force->addExclusion(0, 1);
    w.force->addExclusion(7, 2);
    StickyDipoleForce::SiteParameters other = StickyDipoleForce::getModelParameters("SSD1");
    for (int i = 0; i < w.force->getNumSites(); i += 3)
        w.force->setSiteParameters(i, 3*i, 3*i+1, 3*i+2, other);
    auto evaluate = [&] (const PlatformConfig& config, std::vector<Vec3>& forces) {
        VerletIntegrator integrator(0.001);
        std::unique_ptr<Context> context(createContext(w.system, integrator, config));
        context->setPositions(w.positions);
        State state = context->getState(State::Energy | State::Forces);
        forces = state.getForces();
        return state.getPotentialEnergy();
    };
    PlatformConfig reference;
    reference.platform = "Reference";
    reference.precision = "double";
    std::vector<Vec3> expectedForces, forces;
    double expected = evaluate(reference, expectedForces), energy = evaluate(GetParam(), forces);
    double largest = 0;
    for (const Vec3& f : expectedForces)
        largest = std::max(largest, std::sqrt(f.dot(f)));
    double worst = maxDistance(forces, expectedForces);
    bool isDouble = (GetParam().precision == "double");
    std::cout << GetParam().name() << ": energy " << energy << " kJ/mol, relative difference " << (energy-expected)/std::abs(expected)
              << "; largest force difference " << worst << " of " << largest << " kJ/mol/nm" << std::endl;
    EXPECT_NEAR(expected, energy, (isDouble ? 1e-10 : 1e-6)*std::abs(expected));
    EXPECT_LT(worst, (isDouble ? 1e-9 : 1e-5)*largest);
}

GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(StickyDipoleForceParity);
INSTANTIATE_TEST_SUITE_P(OnPlatform, StickyDipoleForceParity, testing::ValuesIn(nonReferenceConfigs()), PlatformConfigName());
