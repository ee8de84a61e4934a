// What warm starts save in the matrix-free coupled friction step (HydrodynamicInteractions::
// krylovFrictionStep): a suspension of 15-blob boomerangs (two arms of 7 blobs spaced 0.3 nm
// meeting at a corner, blob radius 0.25 nm, 40 amu a blob, at 5% volume fraction in water,
// viscosity 536 amu/(nm ps), 300 K, h = 2 fs) moved for a few hundred steps of the friction step
// and free drifts. Each step is solved twice from the same states and normal numbers: by an
// interactions object whose friction solve starts from the best multiple of its last solution
// (warm), and by one that starts from zero (cold); the trajectory follows the warm one.
//
//   benchmark_warm_start results.csv [--bodies 64] [--steps 300] [--tolerance 1e-10] [--kT 2.494]
//
// It prints the friction solve's products per step (the warm start's own product included) with
// their standard errors, the products of the whole step, and the largest relative difference of
// the two steps' velocities (which the tolerance bounds). OPENMM_CPU_THREADS sets the threads.

#include "internal/BlobMobility.h"
#include "internal/BodyDynamics.h"
#include "internal/HydrodynamicInteractions.h"
#include "internal/RigidBodyModel.h"
#include "openmm/System.h"
#include "BenchmarkTiming.h"
#include <Eigen/Geometry>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>

using namespace RigidLangevinPlugin;
using namespace BenchmarkTiming;
using OpenMM::Vec3;

namespace {

const double Spacing = 0.3, BlobRadius = 0.25, BlobMass = 40, VolumeFraction = 0.05, Viscosity = 536, StepSize = 0.002;

/** n boomerangs at random centres and orientations in a cube at VolumeFraction (overlaps allowed). */
void boomerangs(int n, OpenMM::System& system, RigidBodyDescription& description, vector<Vec3>& positions, std::mt19937& random) {
    vector<Vec3> shape = {Vec3(0, 0, 0)};
    for (int k = 1; k <= 7; k++) {
        shape.push_back(Vec3(k*Spacing, 0, 0));
        shape.push_back(Vec3(0, k*Spacing, 0));
    }
    const double side = std::cbrt(n*15*4*M_PI/3*std::pow(BlobRadius, 3)/VolumeFraction);
    std::uniform_real_distribution<double> uniform(0, 1);
    std::normal_distribution<double> normal;
    description.hydrodynamicInteractions = true;
    for (int b = 0; b < n; b++) {
        Eigen::Quaterniond q(normal(random), normal(random), normal(random), normal(random));
        Eigen::Matrix3d rotation = q.normalized().toRotationMatrix();
        Vec3 centre(side*uniform(random), side*uniform(random), side*uniform(random));
        RigidBodyDescription::Body body;
        for (const Vec3& p : shape) {
            Eigen::Vector3d r = rotation*Eigen::Vector3d(p[0], p[1], p[2]);
            body.particles.push_back(system.addParticle(BlobMass));
            description.particleRadii[body.particles.back()] = BlobRadius;
            positions.push_back(centre+Vec3(r[0], r[1], r[2]));
        }
        description.bodies.push_back(body);
    }
}

struct Totals {
    vector<double> warm, cold, warmStep, coldStep;
    double maxDifference = 0;
};

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') {
        std::cerr << "usage: " << argv[0] << " results.csv [--bodies 64] [--steps 300] [--tolerance 1e-10] [--kT 2.494]" << std::endl;
        return 2;
    }
    int numBodies = 64, steps = 300;
    double tolerance = 1e-10, kT = 2.494;
    if (!readOptions(argc, argv, {{"--bodies", [&] (const char* v) { numBodies = std::atoi(v); }},
                                  {"--steps", [&] (const char* v) { steps = std::atoi(v); }},
                                  {"--tolerance", [&] (const char* v) { tolerance = std::atof(v); }},
                                  {"--kT", [&] (const char* v) { kT = std::atof(v); }}}))
        return 2;
    std::mt19937 random(7);
    std::normal_distribution<double> normal;
    OpenMM::System system;
    RigidBodyDescription description;
    vector<Vec3> positions;
    boomerangs(numBodies, system, description, positions, random);
    vector<Vec3> velocities(positions.size());
    for (Vec3& v : velocities)
        v = Vec3(normal(random), normal(random), normal(random))*std::sqrt(kT/BlobMass);
    RigidBodyModel model(system, description);
    vector<BodyState> states = model.fitStates(positions, velocities, NULL);
    HydrodynamicInteractions warm(model), cold(model);
    cold.setWarmStarts(false);
    OpenMM::ThreadPool pool(numThreads());
    HostBlobMobility mobility(poolParallel(pool));
    Totals totals;
    for (int step = 0; step < steps; step++) {
        Eigen::VectorXd normals(3*warm.getNumBlobs());
        for (int i = 0; i < normals.size(); i++)
            normals[i] = normal(random);
        Eigen::VectorXd uWarm = warm.getVelocities(states), uCold = uWarm;
        HydrodynamicInteractions::KrylovIterations w = warm.krylovFrictionStep(states, Viscosity, kT, StepSize, normals, uWarm, tolerance, 1000, mobility);
        HydrodynamicInteractions::KrylovIterations c = cold.krylovFrictionStep(states, Viscosity, kT, StepSize, normals, uCold, tolerance, 1000, mobility);
        // The warm start's scaling takes one product (none on the first step, with nothing to start from).
        const int startProducts = (step > 0 ? 1 : 0);
        totals.warm.push_back(w.friction+startProducts);
        totals.cold.push_back(c.friction);
        totals.warmStep.push_back(w.noise+w.noiseSolve+w.friction+startProducts);
        totals.coldStep.push_back(c.noise+c.noiseSolve+c.friction);
        totals.maxDifference = std::max(totals.maxDifference, (uWarm-uCold).norm()/uCold.norm());
        warm.setVelocities(uWarm, states);
        for (int b = 0; b < model.getNumBodies(); b++)
            BodyDynamics::drift(states[b], model.getType(model.getBodyType(b)), StepSize);
    }
    double warmMean, warmSe, coldMean, coldSe, warmStep, warmStepSe, coldStep, coldStepSe;
    meanAndError(totals.warm, warmMean, warmSe);
    meanAndError(totals.cold, coldMean, coldSe);
    meanAndError(totals.warmStep, warmStep, warmStepSe);
    meanAndError(totals.coldStep, coldStep, coldStepSe);
    vector<double> saved;
    for (size_t i = 0; i < totals.warm.size(); i++)
        saved.push_back(totals.cold[i]-totals.warm[i]);
    double savedMean, savedSe;
    meanAndError(saved, savedMean, savedSe);
    printf("%d boomerangs (%d blobs), %d steps, tolerance %g, kT %g\n", numBodies, warm.getNumBlobs(), steps, tolerance, kT);
    printf("friction products per step: cold %.2f ± %.2f, warm %.2f ± %.2f (its start's product included), saved %.2f ± %.2f\n", coldMean, coldSe,
           warmMean, warmSe, savedMean, savedSe);
    printf("products per step, all solves: cold %.2f ± %.2f, warm %.2f ± %.2f; largest relative difference of the velocities %.1e\n", coldStep,
           coldStepSe, warmStep, warmStepSe, totals.maxDifference);
    std::ofstream csv(argv[1]);
    csv << "bodies,blobs,steps,tolerance,kT,cold_friction_products,cold_se,warm_friction_products,warm_se,saved,saved_se,cold_step_products,"
           "cold_step_se,warm_step_products,warm_step_se,max_relative_velocity_difference\n";
    csv << numBodies << "," << warm.getNumBlobs() << "," << steps << "," << tolerance << "," << kT << "," << coldMean << "," << coldSe << ","
        << warmMean << "," << warmSe << "," << savedMean << "," << savedSe << "," << coldStep << "," << coldStepSe << "," << warmStep << ","
        << warmStepSe << "," << totals.maxDifference << "\n";
    return 0;
}
