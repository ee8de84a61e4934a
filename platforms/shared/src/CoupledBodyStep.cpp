#include "internal/CoupledBodyStep.h"
#include "internal/BodyDynamics.h"
#include <cmath>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

namespace {

/** Make a body's rotation orthonormal again (Gram-Schmidt on its rows), in double precision. */
void orthonormalize(double q[3][3]) {
    Vec3 row0(q[0][0], q[0][1], q[0][2]), row1(q[1][0], q[1][1], q[1][2]);
    row0 /= std::sqrt(row0.dot(row0));
    row1 -= row0*row0.dot(row1);
    row1 /= std::sqrt(row1.dot(row1));
    Vec3 row2 = row0.cross(row1);
    for (int j = 0; j < 3; j++) {
        q[0][j] = row0[j];
        q[1][j] = row1[j];
        q[2][j] = row2[j];
    }
}

} // namespace

CoupledBodyStep::CoupledBodyStep(const RigidBodyModel& model, const HydrodynamicInteractions& interactions) : model(model), interactions(interactions) {
}

void CoupledBodyStep::take(vector<BodyState>& states, const vector<Vec3>& forces, const CoupledStepParameters& step, const CoupledSolve& solve,
                           const std::function<double ()>& normal, BlobMobility& mobility, const KrylovSolvers::ParallelFor& parallel) {
    const double h = step.stepSize;
    parallel(states.size(), [&] (int begin, int end) {
        for (int b = begin; b < end; b++) {
            const BodyType& type = model.getType(model.getBodyType(b));
            BodyState& s = states[b];
            orthonormalize(s.rotation);
            Vec3 force, torque;
            BodyDynamics::gatherForce(type, model.getBodyParticles(b), s, forces, force, torque);
            BodyDynamics::kick(s, type, force, torque, h);
            BodyDynamics::drift(s, type, 0.5*h);
        }
    });
    frictionStep(states, step, solve, normal, mobility);
    parallel(states.size(), [&] (int begin, int end) {
        for (int b = begin; b < end; b++)
            BodyDynamics::drift(states[b], model.getType(model.getBodyType(b)), 0.5*h);
    });
}

void CoupledBodyStep::frictionStep(vector<BodyState>& states, const CoupledStepParameters& step, const CoupledSolve& solve,
                                   const std::function<double ()>& normal, BlobMobility& mobility) {
    Eigen::VectorXd u = interactions.getVelocities(states);
    if (solve.krylov) {
        Eigen::VectorXd normals(3*interactions.getNumBlobs());
        for (int i = 0; i < normals.size(); i++)
            normals[i] = (step.kT > 0 ? normal() : 0.0);
        lastIterations = interactions.krylovFrictionStep(states, step.viscosity, step.kT, step.stepSize, normals, u, solve.tolerance,
                                                         solve.maxIterations, mobility, step.box);
    }
    else {
        Eigen::MatrixXd resistance = interactions.computeResistance(states, step.box);
        Eigen::VectorXd normals(u.size());
        for (int i = 0; i < u.size(); i++)
            normals[i] = normal();
        midpointFrictionStep(resistance, interactions.getMasses(), step.viscosity, step.kT, step.stepSize, normals, u);
        lastIterations = {0, 0, 0};
    }
    interactions.setVelocities(u, states);
}
