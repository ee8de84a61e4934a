/*
 * OpenMM's GPU platforms reorder atoms every 250 steps (and when positions are set) for their
 * neighbour lists, and wrap each "molecule" (atoms linked by bonds, constraints or exceptions) into
 * the periodic box, keeping its cell offset. Rigid bodies are not molecules to OpenMM: here every
 * body is three identical, unbonded atoms, so OpenMM sees 144 identical one-atom molecules and
 * shuffles atoms between bodies and wraps them one by one. Bodies start straddling the box faces.
 * Over 600 steps (several reorders) every body must stay whole and rigid, and the trajectory must
 * follow Reference's (which never reorders), at zero temperature with friction and without friction
 * (where the Lennard-Jones fluid is chaotic). A particle followed to the wrong place, or a body cut
 * by the box, would be off by 0.1 to 2 nm; the tolerances are the spread of Reference's own
 * trajectory from a start displaced by 1e-9 nm (double) or 1e-5 nm, at least 1e-6 nm (double: GPU
 * forces in fixed point differ from Reference's by ~1e-7 kJ/mol/nm) or 1e-4 nm. Equality of the
 * equations themselves is TestPlatformParity's job.
 *
 * Rigidity is measured from the first step on: in mixed precision OpenMM itself rounds wrapped
 * positions to single precision when it reorders them after setPositions (~1e-7 nm), and bodies
 * take their shapes from the positions the platform holds.
 */
#include "RigidBodyTestUtilities.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/VirtualSite.h"
#include <gtest/gtest.h>
#include <memory>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

const int NumSteps = 600;
const double BoxSize = 2.4;

/** 48 triangular bodies of three identical unbonded atoms on a lattice shifted across the box faces. */
struct ShuffledFluid {
    System system;
    std::vector<Vec3> positions;
    std::vector<std::vector<int> > bodies;
    ShuffledFluid() {
        system.setDefaultPeriodicBoxVectors(Vec3(BoxSize, 0, 0), Vec3(0, BoxSize, 0), Vec3(0, 0, BoxSize));
        NonbondedForce* nb = new NonbondedForce();
        nb->setNonbondedMethod(NonbondedForce::CutoffPeriodic);
        nb->setCutoffDistance(0.8);
        nb->setUseSwitchingFunction(true);  // forces continuous at the cutoff, where platforms may round differently
        nb->setSwitchingDistance(0.65);
        const Vec3 triangle[3] = {Vec3(0, 0, 0), Vec3(0.3, 0, 0), Vec3(0.1, 0.26, 0.05)};
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                for (int k = 0; k < 3; k++) {
                    Vec3 corner(0.6*i-0.2, 0.6*j-0.15, 0.78*k-0.1);
                    std::vector<int> body;
                    for (const Vec3& offset : triangle) {
                        body.push_back(system.addParticle(12.0));
                        nb->addParticle(0.0, 0.25, 0.5);
                        positions.push_back(corner+offset);
                    }
                    bodies.push_back(body);
                }
        system.addForce(nb);
    }
};

/** Positions after NumSteps steps; afterFirstStep receives those after the first. */
std::vector<Vec3> trajectoryEnd(const PlatformConfig& config, double temperature, double viscosity, double displacement = 0,
                                std::vector<Vec3>* afterFirstStep = nullptr) {
    ShuffledFluid fluid;
    RigidLangevinIntegrator integrator(temperature, viscosity, 0.002);
    for (const std::vector<int>& body : fluid.bodies)
        integrator.addRigidBody(body);
    std::unique_ptr<Context> context(createContext(fluid.system, integrator, config));
    std::vector<Vec3> positions = fluid.positions;
    for (int i = 0; i < 3; i++)
        positions[i][0] += displacement;
    context->setPositions(positions);
    // Velocities drawn on Reference, so that every platform starts from the same ones.
    ShuffledFluid reference;
    RigidLangevinIntegrator referenceIntegrator(300, 0, 0.002);
    for (const std::vector<int>& body : reference.bodies)
        referenceIntegrator.addRigidBody(body);
    Context referenceContext(reference.system, referenceIntegrator, Platform::getPlatformByName("Reference"));
    referenceContext.setPositions(positions);
    referenceContext.setVelocitiesToTemperature(300, 3);
    context->setVelocities(referenceContext.getState(State::Velocities).getVelocities());
    integrator.step(1);
    if (afterFirstStep != nullptr)
        *afterFirstStep = context->getState(State::Positions).getPositions();
    integrator.step(NumSteps-1);
    return context->getState(State::Positions).getPositions();
}

PlatformConfig reference() {
    PlatformConfig c;
    c.platform = "Reference";
    c.precision = "double";
    return c;
}

} // namespace

class AtomReordering : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(AtomReordering, BodiesStayWholeAndFollowReference) {
    const PlatformConfig& config = GetParam();
    bool exact = (config.precision == "double" && config.platform != "CPU");
    ShuffledFluid fluid;
    std::vector<Vec3> start;
    for (double viscosity : {30.0, 0.0}) {
        double temperature = (viscosity > 0 ? 0.0 : 300.0);
        SCOPED_TRACE("viscosity "+std::to_string(viscosity));
        std::vector<Vec3> expected = trajectoryEnd(reference(), temperature, viscosity);
        std::vector<Vec3> result = trajectoryEnd(config, temperature, viscosity, 0, &start);
        double displacement = (exact ? 1e-9 : 1e-5);
        double spread = maxDistance(expected, trajectoryEnd(reference(), temperature, viscosity, displacement));
        double tolerance = std::max(spread, exact ? 1e-6 : 1e-4);
        double distance = maxDistance(expected, result);
        std::cout << config.name() << ", viscosity " << viscosity << ": largest distance from Reference after " << NumSteps
                  << " steps " << distance << " nm (Reference from a start " << displacement << " nm away: " << spread << " nm)" << std::endl;
        EXPECT_LT(distance, tolerance);
        // Every body whole and rigid: its particles' distances as after the first step, none wrapped apart.
        double worst = 0;
        for (const std::vector<int>& body : fluid.bodies)
            for (int i : body)
                for (int j : body)
                    if (i < j) {
                        Vec3 d0 = start[i]-start[j], d1 = result[i]-result[j];
                        worst = std::max(worst, std::abs(std::sqrt(d1.dot(d1))-std::sqrt(d0.dot(d0))));
                    }
        EXPECT_LT(worst, config.precision == "single" ? 1e-5 : 1e-9);
    }
}

/*
 * What links particles of different bodies, or a body and a particle outside every body, must see
 * them in one periodic frame: OpenMM computes a virtual site from its parents' stored positions and
 * a bond without periodic boundaries from its ends' stored positions, and keeps each molecule (atoms
 * linked by bonds, constraints or sites) in one frame when it wraps atoms; bodies must not split
 * that frame. 27 three-particle waters straddling the box faces, each with its M site left out of
 * its body; nine sites midway between the oxygens of two bodies; nine bonds between the oxygens of
 * two other bodies, and one to a massless particle in no body, which stays put. At 300 K over 600
 * steps (two reorderings) bodies cross the faces. Every site must be where its definition puts it
 * from its parents' reported positions, and the bonds' energy on the platform must be the one the
 * reported positions give: a particle stored in another frame than its partners would be off by a
 * box vector (2.4 nm), and a bond's energy by orders of magnitude.
 */
TEST_P(AtomReordering, ParticlesLinkedAcrossBodiesStayInOneFrame) {
    const PlatformConfig& config = GetParam();
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(BoxSize, 0, 0), Vec3(0, BoxSize, 0), Vec3(0, 0, BoxSize));
    NonbondedForce* nb = new NonbondedForce();
    nb->setNonbondedMethod(NonbondedForce::CutoffPeriodic);
    nb->setCutoffDistance(0.7);
    system.addForce(nb);
    RigidLangevinIntegrator integrator(300, 1.0, 0.002);
    integrator.setRandomNumberSeed(4);
    std::vector<Vec3> positions;
    std::vector<int> oxygens, sites;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) {
                Vec3 oxygen(0.8*i-0.03, 0.8*j+0.02, 0.8*k-0.05);
                int o = system.addParticle(16.0), h1 = system.addParticle(1.0), h2 = system.addParticle(1.0), m = system.addParticle(0.0);
                nb->addParticle(0.0, 0.3, 0.5);
                for (int n = 0; n < 3; n++)
                    nb->addParticle(0.0, 1.0, 0.0);
                positions.push_back(oxygen);
                positions.push_back(oxygen+Vec3(0.09572, 0, 0));
                positions.push_back(oxygen+Vec3(-0.02399, 0.09266, 0));
                positions.push_back(Vec3());
                system.setVirtualSite(m, new ThreeParticleAverageSite(o, h1, h2, 0.786646558, 0.106676721, 0.106676721));
                integrator.addRigidBody({o, h1, h2});
                for (int a : {o, h1, h2})
                    integrator.setParticleRadius(a, 0.1);
                oxygens.push_back(o);
                sites.push_back(m);
            }
    for (int i = 0; i < 9; i++) {
        int link = system.addParticle(0.0);
        nb->addParticle(0.0, 1.0, 0.0);
        positions.push_back(Vec3());
        system.setVirtualSite(link, new TwoParticleAverageSite(oxygens[i], oxygens[i+9], 0.5, 0.5));
        sites.push_back(link);
    }
    HarmonicBondForce* bonds = new HarmonicBondForce();
    bonds->setForceGroup(1);
    for (int i = 9; i < 18; i++)
        bonds->addBond(oxygens[i], oxygens[i+9], 0.8, 50.0);
    int anchor = system.addParticle(0.0);
    nb->addParticle(0.0, 1.0, 0.0);
    positions.push_back(Vec3(2.37, 2.35, 0.3));
    bonds->addBond(anchor, oxygens[26], 0.3, 50.0);
    system.addForce(bonds);
    std::unique_ptr<Context> context(createContext(system, integrator, config));
    context->setPositions(positions);
    context->computeVirtualSites();
    context->setVelocitiesToTemperature(300, 5);
    integrator.step(600);
    std::vector<Vec3> result = context->getState(State::Positions).getPositions();
    double worst = 0, moved = 0;
    for (int p : sites) {
        const VirtualSite& site = system.getVirtualSite(p);
        Vec3 expected;
        for (int i = 0; i < site.getNumParticles(); i++) {
            double weight = (dynamic_cast<const ThreeParticleAverageSite*>(&site) != nullptr ?
                    dynamic_cast<const ThreeParticleAverageSite&>(site).getWeight(i) : dynamic_cast<const TwoParticleAverageSite&>(site).getWeight(i));
            expected += result[site.getParticle(i)]*weight;
        }
        worst = std::max(worst, std::sqrt((result[p]-expected).dot(result[p]-expected)));
    }
    for (int o : oxygens)
        moved = std::max(moved, std::sqrt((result[o]-positions[o]).dot(result[o]-positions[o])));
    std::cout << config.name() << ": largest distance of a site from where its parents put it " << worst << " nm; oxygens moved up to " << moved << " nm" << std::endl;
    EXPECT_LT(worst, config.precision == "double" ? 1e-9 : 1e-5);  // mixed: OpenMM computes sites from float positions
    EXPECT_GT(moved, 0.1);  // far enough for bodies to have crossed the faces they straddled
    double energy = 0;
    for (int b = 0; b < bonds->getNumBonds(); b++) {
        int i, j;
        double length, k;
        bonds->getBondParameters(b, i, j, length, k);
        double r = std::sqrt((result[i]-result[j]).dot(result[i]-result[j]));
        energy += 0.5*k*(r-length)*(r-length);
    }
    double platformEnergy = context->getState(State::Energy, false, 1<<1).getPotentialEnergy();
    std::cout << config.name() << ": bond energy " << platformEnergy << " kJ/mol, from the reported positions " << energy << std::endl;
    // (A bond stretched by a box vector would add ~140 kJ/mol; a GPU sums energies in its own order.)
    EXPECT_NEAR(energy, platformEnergy, (config.precision == "double" ? 1e-6 : 1e-4)*std::max(1.0, energy));
    EXPECT_LT(std::sqrt((result[anchor]-positions[anchor]).dot(result[anchor]-positions[anchor])), config.precision == "double" ? 1e-12 : 1e-6);
}

GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(AtomReordering);
INSTANTIATE_TEST_SUITE_P(OnPlatform, AtomReordering, testing::ValuesIn(nonReferenceConfigs()), PlatformConfigName());
