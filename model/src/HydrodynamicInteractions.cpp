#include "internal/HydrodynamicInteractions.h"
#include "internal/BodyDynamics.h"
#include "internal/CoupledResistanceMath.h"
#include "openmm/OpenMMException.h"
#include <Eigen/Cholesky>
#include <cmath>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

HydrodynamicInteractions::HydrodynamicInteractions(const RigidBodyModel& model) : model(model) {
    for (int t = 0; t < model.getNumTypes(); t++) {
        const BodyType& type = model.getType(t);
        TypeBlobs blobs;
        model.getTypeBlobs(t, blobs.coords, blobs.radii);
        std::string caller = "RigidLangevinIntegrator: hydrodynamic interactions of "+model.getBodyName(model.getFirstBodyOfType(t));
        // The blobs' resistance alone and the body's own friction, in its frame about its centre
        // of mass, over the motions it makes.
        Eigen::MatrixXd alone = CoupledResistanceMath::resistance(caller, blobs.coords, blobs.radii, vector<int>(blobs.coords.size(), 0), {Vec3()});
        vector<int> active = type.getActiveCoordinates();
        int n = active.size();
        Eigen::MatrixXd d(n, n), own(n, n);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                d(i, j) = alone(active[i], active[j]);
                own(i, j) = type.resistance(active[i], active[j]);
            }
        Eigen::MatrixXd calibration = CoupledResistanceMath::calibration(caller, d, own);
        blobs.calibration.setZero();
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                blobs.calibration(active[i], active[j]) = calibration(i, j);
        types.push_back(blobs);
    }
    int numCoordinates = 0;
    for (int b = 0; b < model.getNumBodies(); b++) {
        firstCoordinate.push_back(numCoordinates);
        numCoordinates += model.getType(model.getBodyType(b)).getNumDegreesOfFreedom();
    }
    masses.resize(numCoordinates);
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        vector<int> active = type.getActiveCoordinates();
        for (int i = 0; i < (int) active.size(); i++)
            masses[firstCoordinate[b]+i] = (active[i] < 3 ? type.mass : type.inertia[active[i]-3]);
    }
}

int HydrodynamicInteractions::getNumBlobs() const {
    int count = 0;
    for (int b = 0; b < model.getNumBodies(); b++)
        count += types[model.getBodyType(b)].coords.size();
    return count;
}

Eigen::MatrixXd HydrodynamicInteractions::computeResistance(const vector<BodyState>& states, const Vec3* boxVectors) const {
    const int numBodies = model.getNumBodies();
    vector<Vec3> positions, origins;
    vector<double> radii;
    vector<int> owner;
    for (int b = 0; b < numBodies; b++) {
        const TypeBlobs& blobs = types[model.getBodyType(b)];
        for (int k = 0; k < (int) blobs.coords.size(); k++) {
            positions.push_back(states[b].position+BodyDynamics::toLab(states[b].rotation, blobs.coords[k]));
            radii.push_back(blobs.radii[k]);
            owner.push_back(b);
        }
        origins.push_back(states[b].position);
    }
    Eigen::MatrixXd r = CoupledResistanceMath::resistance("RigidLangevinIntegrator: hydrodynamic interactions (blobs numbered across all bodies in order, "
            "free particles last)", positions, radii, owner, origins, boxVectors);
    // Each body's rows and columns into its frame (Q, lab to body, on its force and its torque),
    // then calibrated: T_a R_ab T_b.
    for (int b = 0; b < numBodies; b++) {
        Eigen::Matrix<double, 6, 6> g = Eigen::Matrix<double, 6, 6>::Zero();
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                g(i, j) = g(i+3, j+3) = states[b].rotation[i][j];
        Eigen::Matrix<double, 6, 6> transform = types[model.getBodyType(b)].calibration*g;
        r.middleRows(6*b, 6) = (transform*r.middleRows(6*b, 6)).eval();
        r.middleCols(6*b, 6) = (r.middleCols(6*b, 6)*transform.transpose()).eval();
    }
    // The active coordinates only.
    vector<int> index;
    for (int b = 0; b < numBodies; b++)
        for (int c : model.getType(model.getBodyType(b)).getActiveCoordinates())
            index.push_back(6*b+c);
    const int n = index.size();
    Eigen::MatrixXd active(n, n);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            active(i, j) = r(index[i], index[j]);
    return 0.5*(active+active.transpose());
}

Eigen::VectorXd HydrodynamicInteractions::getVelocities(const vector<BodyState>& states) const {
    Eigen::VectorXd u(getNumCoordinates());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        Vec3 v = BodyDynamics::toBody(states[b].rotation, states[b].velocity);
        int c = firstCoordinate[b];
        for (int k = 0; k < 3; k++)
            u[c++] = v[k];
        for (int axis = 0; axis < 3; axis++)
            if (type.rotates(axis))
                u[c++] = states[b].angularMomentum[axis]/type.inertia[axis];
    }
    return u;
}

void HydrodynamicInteractions::setVelocities(const Eigen::VectorXd& u, vector<BodyState>& states) const {
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        int c = firstCoordinate[b];
        states[b].velocity = BodyDynamics::toLab(states[b].rotation, Vec3(u[c], u[c+1], u[c+2]));
        c += 3;
        for (int axis = 0; axis < 3; axis++)
            states[b].angularMomentum[axis] = (type.rotates(axis) ? type.inertia[axis]*u[c++] : 0.0);
    }
}

void RigidLangevinPlugin::midpointFrictionStep(const Eigen::MatrixXd& resistance, const Eigen::VectorXd& masses, double viscosity, double kT,
                                               double h, const Eigen::VectorXd& normals, Eigen::VectorXd& u) {
    const double half = 0.5*h*viscosity;
    Eigen::VectorXd rhs = masses.cwiseProduct(u)-half*(resistance*u);
    if (kT > 0) {
        Eigen::LLT<Eigen::MatrixXd> root(resistance);
        if (root.info() != Eigen::Success)
            throw OpenMMException("RigidLangevinIntegrator: the bodies' coupled resistance is not positive definite");
        Eigen::VectorXd noise = root.matrixL()*normals;
        rhs += std::sqrt(2*kT*h*viscosity)*noise;
    }
    Eigen::MatrixXd a = resistance*half;
    a.diagonal() += masses;
    Eigen::LLT<Eigen::MatrixXd> solver(a);
    if (solver.info() != Eigen::Success)
        throw OpenMMException("RigidLangevinIntegrator: the bodies' coupled friction step could not be solved (its matrix is not positive definite)");
    u = solver.solve(rhs);
}
