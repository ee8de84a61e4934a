#include "internal/RigidBodyModel.h"
#include "internal/ResistanceMath.h"
#include "RigidLangevinIntegrator.h"
#include "ResistanceTensor.h"
#include "openmm/AndersenThermostat.h"
#include "openmm/MonteCarloAnisotropicBarostat.h"
#include "openmm/MonteCarloBarostat.h"
#include "openmm/MonteCarloFlexibleBarostat.h"
#include "openmm/MonteCarloMembraneBarostat.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <istream>
#include <ostream>
#include <sstream>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::ResistanceMath;
using namespace OpenMM;
using std::string;
using std::vector;

namespace {

string str(double x) {
    std::ostringstream s;
    s.precision(6);
    s << x;
    return s.str();
}

string bodyName(int body, int numUserBodies, const vector<int>& particles) {
    if (body < numUserBodies)
        return "rigid body "+std::to_string(body);
    return "free particle "+std::to_string(particles[0]);
}

Eigen::Matrix3d toMatrix3(const double q[3][3]) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m(i, j) = q[i][j];
    return m;
}

void fromMatrix3(const Eigen::Matrix3d& m, double q[3][3]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            q[i][j] = m(i, j);
}

/** Relative size below which a principal moment counts as zero (a linear or point body). */
const double ZeroMomentTolerance = 1e-10;

} // namespace

vector<int> BodyType::getActiveCoordinates() const {
    vector<int> active = {0, 1, 2};
    for (int axis = 0; axis < 3; axis++)
        if (rotates(axis))
            active.push_back(3+axis);
    return active;
}

RigidBodyModel::RigidBodyModel(const System& system, const RigidLangevinIntegrator& integrator) {
    int numParticles = system.getNumParticles();
    numUserBodies = integrator.getNumRigidBodies();
    particleBody.assign(numParticles, -1);
    particleMass.resize(numParticles);
    for (int i = 0; i < numParticles; i++)
        particleMass[i] = system.getParticleMass(i);

    // User bodies: indices in range, no particle in two bodies, some mass.
    for (int b = 0; b < numUserBodies; b++) {
        const vector<int>& particles = integrator.getRigidBodyParticles(b);
        double mass = 0;
        for (int p : particles) {
            if (p < 0 || p >= numParticles)
                throw OpenMMException("RigidLangevinIntegrator: rigid body "+std::to_string(b)+" contains particle "+std::to_string(p)+
                        ", but the System has only "+std::to_string(numParticles)+" particles");
            if (particleBody[p] == b)
                throw OpenMMException("RigidLangevinIntegrator: rigid body "+std::to_string(b)+" lists particle "+std::to_string(p)+" twice");
            if (particleBody[p] != -1)
                throw OpenMMException("RigidLangevinIntegrator: particle "+std::to_string(p)+" is in rigid body "+std::to_string(particleBody[p])+
                        " and in rigid body "+std::to_string(b)+"; a particle can belong to one body only");
            particleBody[p] = b;
            mass += particleMass[p];
        }
        if (!(mass > 0))
            throw OpenMMException("RigidLangevinIntegrator: rigid body "+std::to_string(b)+" has no particle with mass; a body needs mass to move (massless sites must ride on a body that has mass)");
        bodyParticles.push_back(particles);
    }

    // Free particles with mass move as single-particle bodies; massless ones stay where they are.
    for (int p = 0; p < numParticles; p++)
        if (particleBody[p] == -1 && particleMass[p] != 0) {
            particleBody[p] = bodyParticles.size();
            bodyParticles.push_back({p});
        }

    // Forces that move particles or set velocities behind the integrator's back would be undone by
    // the next step, which places particles from the body states.
    for (int i = 0; i < system.getNumForces(); i++) {
        const Force& force = system.getForce(i);
        if (dynamic_cast<const MonteCarloBarostat*>(&force) != NULL || dynamic_cast<const MonteCarloAnisotropicBarostat*>(&force) != NULL ||
                dynamic_cast<const MonteCarloMembraneBarostat*>(&force) != NULL || dynamic_cast<const MonteCarloFlexibleBarostat*>(&force) != NULL)
            throw OpenMMException("RigidLangevinIntegrator: the System has a Monte Carlo barostat (force "+std::to_string(i)+"); barostats move particles "
                    "themselves, which rigid bodies cannot follow yet. Remove it and run at constant volume");
        if (dynamic_cast<const AndersenThermostat*>(&force) != NULL)
            throw OpenMMException("RigidLangevinIntegrator: the System has an AndersenThermostat (force "+std::to_string(i)+"); the integrator is "
                    "its own thermostat. Remove the AndersenThermostat");
    }

    // Constraints inside a body are satisfied by its rigidity; any other one cannot be honoured.
    for (int i = 0; i < system.getNumConstraints(); i++) {
        int p1, p2;
        double distance;
        system.getConstraintParameters(i, p1, p2, distance);
        int b1 = particleBody[p1], b2 = particleBody[p2];
        if (b1 == b2 && b1 != -1 && b1 < numUserBodies)
            continue;
        throw OpenMMException("RigidLangevinIntegrator: constraint "+std::to_string(i)+" between particles "+std::to_string(p1)+" and "+std::to_string(p2)+
                " does not lie inside one rigid body; rigid bodies replace constraints, so put both particles in the same body or remove the constraint");
    }

    // Explicit resistance tensors of user bodies.
    explicitTensor.resize(numUserBodies);
    explicitOrigin.resize(numUserBodies);
    for (int b = 0; b < numUserBodies; b++)
        integrator.getBodyResistance(b, explicitTensor[b], explicitOrigin[b]);

    // Hydrodynamic radii: set explicitly, else sigma/2 of a NonbondedForce with nonzero epsilon.
    // A particle with mass needs one unless its body's friction is given explicitly.
    particleRadius.assign(numParticles, 0.0);
    vector<bool> hasRadius(numParticles, false);
    for (int f = 0; f < system.getNumForces(); f++) {
        const NonbondedForce* nb = dynamic_cast<const NonbondedForce*>(&system.getForce(f));
        if (nb == NULL)
            continue;
        for (int p = 0; p < numParticles; p++) {
            double charge, sigma, epsilon;
            nb->getParticleParameters(p, charge, sigma, epsilon);
            if (!hasRadius[p] && epsilon != 0 && sigma > 0) {
                particleRadius[p] = 0.5*sigma;
                hasRadius[p] = true;
            }
        }
    }
    for (auto& r : integrator.getParticleRadii()) {
        if (r.first >= numParticles)
            throw OpenMMException("RigidLangevinIntegrator: a radius was set for particle "+std::to_string(r.first)+", but the System has only "+std::to_string(numParticles)+" particles");
        particleRadius[r.first] = r.second;
        hasRadius[r.first] = true;
    }
    for (int b = 0; b < getNumBodies(); b++) {
        if (b < numUserBodies && !explicitTensor[b].empty())
            continue;
        for (int p : bodyParticles[b])
            if (particleMass[p] != 0 && !hasRadius[p])
                throw OpenMMException("RigidLangevinIntegrator: particle "+std::to_string(p)+" ("+bodyName(b, numUserBodies, bodyParticles[b])+
                        ") has no hydrodynamic radius: it has no Lennard-Jones sigma with nonzero epsilon in a NonbondedForce. Call setParticleRadius("+
                        std::to_string(p)+", radius), or give the body an explicit tensor with setBodyResistance()");
    }
}

vector<Vec3> RigidBodyModel::unwrappedOffsets(int body, const vector<Vec3>& positions, const Vec3* box, Vec3& centre) const {
    // Every particle is taken at its periodic image nearest the body's first particle, so that a
    // body split across the box by wrapping comes back whole.
    const vector<int>& particles = bodyParticles[body];
    Vec3 first = positions[particles[0]];
    vector<Vec3> rel(particles.size());
    double halfWidth = 0;
    if (box != NULL)
        halfWidth = 0.5*std::min(box[0][0], std::min(box[1][1], box[2][2]));
    for (int i = 0; i < (int) particles.size(); i++) {
        Vec3 d = positions[particles[i]]-first;
        if (box != NULL) {
            d -= box[2]*std::round(d[2]/box[2][2]);
            d -= box[1]*std::round(d[1]/box[1][1]);
            d -= box[0]*std::round(d[0]/box[0][0]);
            double dist = std::sqrt(d.dot(d));
            if (dist >= halfWidth*(1-1e-12))
                throw OpenMMException("RigidLangevinIntegrator: "+bodyName(body, numUserBodies, particles)+" is wider than half the periodic box: particle "+
                        std::to_string(particles[i])+" is "+str(dist)+" nm from particle "+std::to_string(particles[0])+" but half the box is "+str(halfWidth)+
                        " nm. Use a larger box");
        }
        rel[i] = d;
    }
    if (box != NULL) {
        // Particles each within half a box of the first can still span more than half a box
        // together, and then which images belong together is ambiguous.
        for (int i = 0; i < (int) particles.size(); i++)
            for (int j = i+1; j < (int) particles.size(); j++) {
                double dist = std::sqrt((rel[i]-rel[j]).dot(rel[i]-rel[j]));
                if (dist >= halfWidth*(1-1e-12))
                    throw OpenMMException("RigidLangevinIntegrator: "+bodyName(body, numUserBodies, particles)+" is wider than half the periodic box: particles "+
                            std::to_string(particles[i])+" and "+std::to_string(particles[j])+" are "+str(dist)+" nm apart but half the box is "+str(halfWidth)+
                            " nm. Use a larger box");
            }
    }
    double mass = 0;
    Vec3 com;
    for (int i = 0; i < (int) particles.size(); i++) {
        com += rel[i]*particleMass[particles[i]];
        mass += particleMass[particles[i]];
    }
    com /= mass;
    for (Vec3& r : rel)
        r -= com;
    centre = first+com;
    return rel;
}

bool RigidBodyModel::matchType(int type, int body, const vector<Vec3>& offsets, double rotation[3][3], double& deviation, int& worst) const {
    // Kabsch: the rotation A (body frame to lab) minimizing sum |A b_i - d_i|^2, then Q = A^T.
    const BodyType& t = types[type];
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    for (int i = 0; i < (int) offsets.size(); i++)
        h += toEigen(t.coords[i])*toEigen(offsets[i]).transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = ((svd.matrixV()*svd.matrixU().transpose()).determinant() < 0 ? -1 : 1);
    Eigen::Matrix3d a = svd.matrixV()*d*svd.matrixU().transpose();
    deviation = 0;
    worst = 0;
    for (int i = 0; i < (int) offsets.size(); i++) {
        double dev = (a*toEigen(t.coords[i])-toEigen(offsets[i])).norm();
        if (dev > deviation) {
            deviation = dev;
            worst = i;
        }
    }
    fromMatrix3(a.transpose(), rotation);
    return deviation <= GeometryTolerance;
}

Matrix6 RigidBodyModel::bodyFrameResistance(int body, const vector<Vec3>& offsets, const Vec3& centre, const double rotation[3][3]) const {
    Eigen::Matrix3d q = toMatrix3(rotation);
    const vector<int>& particles = bodyParticles[body];
    if (body < numUserBodies && !explicitTensor[body].empty()) {
        // The tensor is given in the lab frame of the first positions about a lab point; express it
        // in the body frame and move it to the centre of mass.
        ResistanceTensor lab = ResistanceTensor::fromMatrix(explicitTensor[body], explicitOrigin[body]);
        Matrix6 xi = Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> >(lab.getMatrix(centre).data());
        return rotate(xi, q);
    }
    // The default model: the particles with a radius as Rotne-Prager-Yamakawa beads (overlapping
    // ones too), with the volume correction of a filling model, V the volume of their union. One
    // particle is a Stokes sphere.
    vector<Vec3> beads;
    vector<double> radii;
    for (int i = 0; i < (int) particles.size(); i++)
        if (particleRadius[particles[i]] > 0) {
            beads.push_back(toVec3(q*toEigen(offsets[i])));
            radii.push_back(particleRadius[particles[i]]);
        }
    if (beads.empty())
        throw OpenMMException("RigidLangevinIntegrator: "+bodyName(body, numUserBodies, particles)+" has no particle with a hydrodynamic radius; "
                "set radii with setParticleRadius() or give it an explicit tensor");
    ResistanceTensor model = ResistanceTensor::beads(beads, radii, ResistanceTensor::unionVolume(beads, radii));
    return Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> >(model.getMatrix(Vec3()).data());
}

int RigidBodyModel::createType(int body, const vector<Vec3>& offsets, const Vec3& centre, double rotation[3][3]) {
    const vector<int>& particles = bodyParticles[body];
    string name = bodyName(body, numUserBodies, particles);
    BodyType t;
    t.mass = 0;
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    double extent = 0;
    for (int i = 0; i < (int) particles.size(); i++) {
        double m = particleMass[particles[i]];
        Eigen::Vector3d r = toEigen(offsets[i]);
        t.masses.push_back(m);
        t.radii.push_back(particleRadius[particles[i]]);
        t.mass += m;
        inertia += m*(r.squaredNorm()*Eigen::Matrix3d::Identity()-r*r.transpose());
        extent = std::max(extent, r.norm());
    }

    // Principal axes, moments ascending, right-handed.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(inertia);
    Eigen::Vector3d moments = eigen.eigenvalues();
    Eigen::Matrix3d axes = eigen.eigenvectors();
    if (axes.determinant() < 0)
        axes.col(2) *= -1;
    double scale = std::max(moments[2], t.mass*extent*extent);
    if (moments[2] <= ZeroMomentTolerance*scale || extent == 0)
        t.numRotations = 0;
    else if (moments[0] <= ZeroMomentTolerance*moments[2])
        t.numRotations = 2;
    else
        t.numRotations = 3;
    if (t.numRotations == 2)
        moments[1] = moments[2] = 0.5*(moments[1]+moments[2]);  // equal by symmetry; exact rotation relies on it
    for (int k = 0; k < 3; k++)
        t.inertia[k] = (t.rotates(k) ? moments[k] : 0.0);
    Eigen::Matrix3d q = (t.numRotations == 0 ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(axes.transpose()));
    fromMatrix3(q, rotation);
    for (int i = 0; i < (int) particles.size(); i++) {
        Eigen::Vector3d b = q*toEigen(offsets[i]);
        // A particle off the axes a body can rotate about would need a torque the body cannot take.
        for (int k = 0; k < 3; k++)
            if (!t.rotates(k)) {
                double off = (t.numRotations == 0 ? b.norm() : std::sqrt(b[1]*b[1]+b[2]*b[2]));
                if (off > GeometryTolerance)
                    throw OpenMMException("RigidLangevinIntegrator: "+name+" has its mass "+(t.numRotations == 0 ? "at one point" : "on one line")+
                            ", but massless particle "+std::to_string(particles[i])+" is "+str(off)+" nm off it, so the body cannot carry it. "
                            "Give that particle mass or move it onto the "+(t.numRotations == 0 ? "point" : "line"));
            }
        if (t.numRotations == 2)
            b[1] = b[2] = 0;
        else if (t.numRotations == 0)
            b.setZero();
        t.coords.push_back(toVec3(b));
    }

    // Friction per unit viscosity in the body frame about the centre of mass.
    t.explicitResistance = (body < numUserBodies && !explicitTensor[body].empty());
    t.resistance = bodyFrameResistance(body, offsets, centre, rotation);
    vector<int> active = t.getActiveCoordinates();
    int dof = active.size();
    Eigen::MatrixXd xi(dof, dof);
    for (int i = 0; i < dof; i++)
        for (int j = 0; j < dof; j++)
            xi(i, j) = t.resistance(active[i], active[j]);
    Eigen::LLT<Eigen::MatrixXd> llt(xi);
    if (llt.info() != Eigen::Success || !xi.allFinite())
        throw OpenMMException("RigidLangevinIntegrator: the friction of "+name+" is not positive definite in the motions it can make; "
                "its hydrodynamic beads do not resist every rotation. Set radii on more of its particles or give it an explicit tensor with setBodyResistance()");
    double maxDiagonal = xi.diagonal().cwiseAbs().maxCoeff();
    bool diagonal = true;
    for (int i = 0; i < dof; i++)
        for (int j = 0; j < dof; j++)
            if (i != j && std::abs(xi(i, j)) > 1e-12*maxDiagonal)
                diagonal = false;
    if (!diagonal)
        t.frictionClass = FrictionClass::Coupled;
    else if (t.numRotations == 0 && xi(0, 0) == xi(1, 1) && xi(1, 1) == xi(2, 2))
        t.frictionClass = FrictionClass::Scalar;
    else
        t.frictionClass = FrictionClass::Diagonal;
    if (diagonal)
        for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++)
                if (i != j)
                    t.resistance(i, j) = 0;
    types.push_back(t);
    return types.size()-1;
}

int RigidBodyModel::findOrCreateType(int body, const vector<Vec3>& offsets, const Vec3& centre, double rotation[3][3]) {
    // Bodies with the same masses, radii and friction model, whose shapes agree up to a rotation,
    // share a type (and take its exact shape).
    const vector<int>& particles = bodyParticles[body];
    vector<double> signature;
    signature.push_back(particles.size());
    for (int p : particles) {
        signature.push_back(particleMass[p]);
        signature.push_back(particleRadius[p]);
    }
    bool isExplicit = (body < numUserBodies && !explicitTensor[body].empty());
    signature.push_back(isExplicit ? 1 : 0);
    auto range = typesBySignature.equal_range(signature);
    for (auto it = range.first; it != range.second; ++it) {
        double deviation;
        int worst;
        if (!matchType(it->second, body, offsets, rotation, deviation, worst))
            continue;
        if (isExplicit) {
            Matrix6 xi = bodyFrameResistance(body, offsets, centre, rotation);
            const Matrix6& typeXi = types[it->second].resistance;
            if ((xi-typeXi).cwiseAbs().maxCoeff() > 1e-8*typeXi.cwiseAbs().maxCoeff())
                continue;
        }
        return it->second;
    }
    int type = createType(body, offsets, centre, rotation);
    typesBySignature.insert(std::make_pair(signature, type));
    return type;
}

vector<BodyState> RigidBodyModel::fitStates(const vector<Vec3>& positions, const vector<Vec3>& velocities, const Vec3* box) {
    bool firstBuild = types.empty();
    if (firstBuild)
        bodyType.resize(getNumBodies());
    vector<BodyState> states(getNumBodies());
    for (int b = 0; b < getNumBodies(); b++) {
        const vector<int>& particles = bodyParticles[b];
        for (int p : particles)
            if (!std::isfinite(positions[p][0]) || !std::isfinite(positions[p][1]) || !std::isfinite(positions[p][2]))
                throw OpenMMException("RigidLangevinIntegrator: particle "+std::to_string(p)+" has a position that is not finite");
        BodyState& s = states[b];
        vector<Vec3> offsets = unwrappedOffsets(b, positions, box, s.position);
        if (firstBuild)
            bodyType[b] = findOrCreateType(b, offsets, s.position, s.rotation);
        else {
            double deviation;
            int worst;
            if (!matchType(bodyType[b], b, offsets, s.rotation, deviation, worst))
                throw OpenMMException("RigidLangevinIntegrator: the positions deform "+bodyName(b, numUserBodies, particles)+": particle "+
                        std::to_string(particles[worst])+" is "+str(deviation)+" nm from its place in the rigid body (tolerance "+str(GeometryTolerance)+
                        " nm). Bodies keep the shape of the positions first set on the Context; to change shapes, call Context.reinitialize()");
        }
        const BodyType& t = types[bodyType[b]];
        if (t.numRotations == 0)
            fromMatrix3(Eigen::Matrix3d::Identity(), s.rotation);

        // Project velocities onto rigid motion: keep the momentum and the angular momentum.
        Vec3 momentum, angular;
        for (int i = 0; i < (int) particles.size(); i++) {
            double m = t.masses[i];
            momentum += velocities[particles[i]]*m;
            angular += offsets[i].cross(velocities[particles[i]])*m;
        }
        s.velocity = momentum/t.mass;
        Eigen::Vector3d j = toMatrix3(s.rotation)*toEigen(angular);
        for (int k = 0; k < 3; k++)
            s.angularMomentum[k] = (t.rotates(k) ? j[k] : 0.0);
    }
    return states;
}

void RigidBodyModel::placeParticles(const vector<BodyState>& states, vector<Vec3>& positions, vector<Vec3>& velocities) const {
    for (int b = 0; b < getNumBodies(); b++) {
        const BodyState& s = states[b];
        const BodyType& t = types[bodyType[b]];
        const vector<int>& particles = bodyParticles[b];
        Vec3 omega;  // body frame
        for (int k = 0; k < 3; k++)
            omega[k] = (t.rotates(k) ? s.angularMomentum[k]/t.inertia[k] : 0.0);
        for (int i = 0; i < (int) particles.size(); i++) {
            const Vec3& c = t.coords[i];
            // Lab-frame offset Q^T b and velocity Q^T (omega x b).
            Vec3 w = omega.cross(c);
            Vec3 offset, vel;
            for (int k = 0; k < 3; k++) {
                offset[k] = s.rotation[0][k]*c[0]+s.rotation[1][k]*c[1]+s.rotation[2][k]*c[2];
                vel[k] = s.rotation[0][k]*w[0]+s.rotation[1][k]*w[1]+s.rotation[2][k]*w[2];
            }
            positions[particles[i]] = s.position+offset;
            velocities[particles[i]] = s.velocity+vel;
        }
    }
}

int RigidBodyModel::getNumRotationalDegreesOfFreedom() const {
    int dof = 0;
    for (int b = 0; b < getNumBodies(); b++)
        dof += types[bodyType[b]].numRotations;
    return dof;
}

int RigidBodyModel::getNumDegreesOfFreedom() const {
    return getNumTranslationalDegreesOfFreedom()+getNumRotationalDegreesOfFreedom();
}

double RigidBodyModel::getTotalMass() const {
    double mass = 0;
    for (int b = 0; b < getNumBodies(); b++)
        mass += types[bodyType[b]].mass;
    return mass;
}

namespace {

template <class T>
void writeValue(std::ostream& stream, const T& value) {
    stream.write((const char*) &value, sizeof(T));
}

template <class T>
void readValue(std::istream& stream, T& value) {
    stream.read((char*) &value, sizeof(T));
}

template <class T>
void writeVector(std::ostream& stream, const vector<T>& values) {
    int size = values.size();
    writeValue(stream, size);
    stream.write((const char*) values.data(), size*sizeof(T));
}

template <class T>
void readVector(std::istream& stream, vector<T>& values) {
    int size;
    readValue(stream, size);
    if (!stream || size < 0 || size > (1<<28))
        throw OpenMMException("RigidLangevinIntegrator: the checkpoint is corrupt");
    values.resize(size);
    stream.read((char*) values.data(), size*sizeof(T));
}

} // namespace

void RigidBodyModel::writeTypes(std::ostream& stream) const {
    int numTypes = types.size();
    writeValue(stream, numTypes);
    for (const BodyType& t : types) {
        writeVector(stream, t.masses);
        writeVector(stream, t.radii);
        writeVector(stream, t.coords);
        writeValue(stream, t.mass);
        writeValue(stream, t.inertia);
        writeValue(stream, t.numRotations);
        writeValue(stream, t.explicitResistance);
        writeValue(stream, t.resistance);
        writeValue(stream, t.frictionClass);
    }
    writeVector(stream, bodyType);
}

void RigidBodyModel::readTypes(std::istream& stream) {
    int numTypes;
    readValue(stream, numTypes);
    if (!stream || numTypes < 0 || numTypes > getNumBodies())
        throw OpenMMException("RigidLangevinIntegrator: the checkpoint is corrupt or was written for another System");
    vector<BodyType> newTypes(numTypes);
    for (BodyType& t : newTypes) {
        readVector(stream, t.masses);
        readVector(stream, t.radii);
        readVector(stream, t.coords);
        readValue(stream, t.mass);
        readValue(stream, t.inertia);
        readValue(stream, t.numRotations);
        readValue(stream, t.explicitResistance);
        readValue(stream, t.resistance);
        readValue(stream, t.frictionClass);
    }
    vector<int> newBodyType;
    readVector(stream, newBodyType);
    bool fits = (stream && (int) newBodyType.size() == getNumBodies());
    for (int b = 0; fits && b < getNumBodies(); b++) {
        int t = newBodyType[b];
        fits = (t >= 0 && t < numTypes && newTypes[t].masses.size() == bodyParticles[b].size());
        for (int i = 0; fits && i < (int) bodyParticles[b].size(); i++)
            fits = (newTypes[t].masses[i] == particleMass[bodyParticles[b][i]]);
    }
    if (!fits)
        throw OpenMMException("RigidLangevinIntegrator: the checkpoint's rigid bodies do not match this System's");
    types = newTypes;
    bodyType = newBodyType;
    typesBySignature.clear();
}
