#ifndef LENNARD_JONES_CLUSTER_H_
#define LENNARD_JONES_CLUSTER_H_

/*
 * The test system of interacting rigid bodies: eight asymmetric bodies on a cube, turned
 * differently, attracting each other through Lennard-Jones (sigma 0.25 nm, epsilon 1 kJ/mol).
 * Optionally with one body of every other kind around it, so that every friction class and every
 * number of rotations is present: two free particles (Scalar), a linear body (two rotations), a
 * body with an explicit sphere tensor (Diagonal, three rotations). The asymmetric bead bodies are
 * Coupled.
 */

#include "RigidBodyTestUtilities.h"
#include "openmm/CustomBondForce.h"
#include "openmm/NonbondedForce.h"
#include <Eigen/Geometry>
#include <memory>

namespace RigidBodyTest {

struct LennardJonesCluster {
    /**
     * How the Lennard-Jones interactions are computed. Nonbonded: a NonbondedForce without cutoff
     * (exclusions inside bodies). PairBonds: the same energy as a CustomBondForce over every pair of
     * particles in different bodies; every platform evaluates custom bonds in the context's own
     * precision (the CPU platform in double, its NonbondedForce in single), which lets a test
     * compare integrators with forces as exact as the precision allows.
     */
    enum Interaction {Nonbonded, PairBonds};
    static const int NumClusterBodies = 8;
    OpenMM::System system;
    std::vector<Vec3> positions;
    std::vector<std::vector<int> > bodies;  ///< user bodies (free particles are in none)
    int sphereBody;                         ///< the body with an explicit sphere tensor, or -1
    explicit LennardJonesCluster(Interaction interaction = Nonbonded, bool otherKinds = false) : sphereBody(-1) {
        BodyShape shape = asymmetricBody();
        int body = 0;
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2; j++)
                for (int k = 0; k < 2; k++, body++) {
                    Eigen::Matrix3d r = Eigen::AngleAxisd(1.1*body, Eigen::Vector3d(1, -2, 3).normalized()).toRotationMatrix();
                    std::vector<int> particles;
                    for (int p = 0; p < 4; p++) {
                        particles.push_back(system.addParticle(shape.masses[p]));
                        positions.push_back(toVec3(0.42*Eigen::Vector3d(i, j, k)+r*shape.reference[p]));
                    }
                    bodies.push_back(particles);
                }
        std::vector<int> owner(positions.size());
        for (int b = 0; b < (int) bodies.size(); b++)
            for (int p : bodies[b])
                owner[p] = b;
        if (otherKinds) {
            // Free particles beside two faces of the cube.
            for (const Vec3& p : {Vec3(-0.38, 0.2, 0.25), Vec3(0.2, 0.8, 0.15)}) {
                owner.push_back(-1-system.getNumParticles());
                system.addParticle(20.0);
                positions.push_back(p);
            }
            // A linear body below it.
            std::vector<int> linear;
            for (int p = -1; p <= 1; p++) {
                linear.push_back(system.addParticle(p == 0 ? 12.0 : 16.0));
                positions.push_back(Vec3(0.21, 0.2+0.116*p, -0.38));
                owner.push_back(bodies.size());
            }
            bodies.push_back(linear);
            // An asymmetric body beside another face, with a sphere tensor.
            std::vector<int> sphere;
            for (int p = 0; p < 4; p++) {
                sphere.push_back(system.addParticle(shape.masses[p]));
                positions.push_back(toVec3(Eigen::Vector3d(0.82, 0.25, 0.2)+shape.reference[p]));
                owner.push_back(bodies.size());
            }
            sphereBody = bodies.size();
            bodies.push_back(sphere);
        }
        int numParticles = system.getNumParticles();
        if (interaction == Nonbonded) {
            OpenMM::NonbondedForce* nb = new OpenMM::NonbondedForce();
            nb->setNonbondedMethod(OpenMM::NonbondedForce::NoCutoff);
            for (int p = 0; p < numParticles; p++)
                nb->addParticle(0.0, 0.25, 1.0);
            for (const std::vector<int>& particles : bodies)
                for (int p = 0; p < (int) particles.size(); p++)
                    for (int q = p+1; q < (int) particles.size(); q++)
                        nb->addException(particles[p], particles[q], 0, 1, 0);
            system.addForce(nb);
        }
        else {
            OpenMM::CustomBondForce* lj = new OpenMM::CustomBondForce("4*((0.25/r)^12-(0.25/r)^6)");
            for (int p = 0; p < numParticles; p++)
                for (int q = p+1; q < numParticles; q++)
                    if (owner[p] != owner[q])
                        lj->addBond(p, q);
            system.addForce(lj);
        }
    }
    void addBodies(RigidLangevinPlugin::RigidLangevinIntegrator& integrator) const {
        for (const std::vector<int>& particles : bodies)
            integrator.addRigidBody(particles);
        for (int p = 0; p < system.getNumParticles(); p++)
            integrator.setParticleRadius(p, 0.1);
        if (sphereBody >= 0) {
            const double a = 0.15;
            Eigen::Matrix<double, 6, 6> sphere = Eigen::Matrix<double, 6, 6>::Zero();
            sphere.block<3, 3>(0, 0) = 6*M_PI*a*Eigen::Matrix3d::Identity();
            sphere.block<3, 3>(3, 3) = 8*M_PI*a*a*a*Eigen::Matrix3d::Identity();
            Vec3 center;
            double mass = 0;
            std::vector<Vec3> reference;
            for (int p : bodies[sphereBody]) {
                center += positions[p]*system.getParticleMass(p);
                mass += system.getParticleMass(p);
                reference.push_back(positions[p]);
            }
            integrator.setBodyResistance(sphereBody, flatten(sphere), center/mass, reference);
        }
    }
};

/**
 * Positions after numSteps steps of 2 fs of the cluster with a body of every other kind, in the
 * given scheme, temperature and viscosity (random number seed 3), from velocities drawn at 300 K on
 * the Reference platform (seed 17), so that every platform starts from the same ones; body 0
 * displaced rigidly along x by displacement (its particles' fit moves the centre).
 */
inline std::vector<Vec3> clusterTrajectoryEnd(const PlatformConfig& config, RigidLangevinPlugin::RigidLangevinIntegrator::Scheme scheme,
        double temperature, double viscosity, LennardJonesCluster::Interaction interaction, int numSteps, double displacement = 0) {
    LennardJonesCluster cluster(interaction, true);
    RigidLangevinPlugin::RigidLangevinIntegrator integrator(temperature, viscosity, 0.002);
    integrator.setScheme(scheme);
    integrator.setRandomNumberSeed(3);
    cluster.addBodies(integrator);
    std::unique_ptr<OpenMM::Context> context(createContext(cluster.system, integrator, config));
    std::vector<Vec3> positions = cluster.positions;
    for (int p = 0; p < 4; p++)
        positions[p][0] += displacement;
    context->setPositions(positions);
    LennardJonesCluster referenceCluster(interaction, true);
    RigidLangevinPlugin::RigidLangevinIntegrator referenceIntegrator(300, 0, 0.002);
    referenceCluster.addBodies(referenceIntegrator);
    OpenMM::Context reference(referenceCluster.system, referenceIntegrator, OpenMM::Platform::getPlatformByName("Reference"));
    reference.setPositions(positions);
    reference.setVelocitiesToTemperature(300, 17);
    context->setVelocities(reference.getState(OpenMM::State::Velocities).getVelocities());
    integrator.step(numSteps);
    return context->getState(OpenMM::State::Positions).getPositions();
}

} // namespace RigidBodyTest

#endif /*LENNARD_JONES_CLUSTER_H_*/
