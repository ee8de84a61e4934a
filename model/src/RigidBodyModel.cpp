#include "internal/RigidBodyModel.h"
#include "internal/ExactBodyShapes.h"
#include "internal/RigidFit.h"
#include "internal/ResistanceMath.h"
#include "ResistanceTensor.h"
#include "openmm/AndersenThermostat.h"
#include "openmm/MonteCarloAnisotropicBarostat.h"
#include "openmm/MonteCarloBarostat.h"
#include "openmm/MonteCarloFlexibleBarostat.h"
#include "openmm/MonteCarloMembraneBarostat.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/VirtualSite.h"
#include "openmm/serialization/SerializationNode.h"
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <istream>
#include <ostream>
#include <sstream>
#if defined(__x86_64__) || defined(_M_X64)
#include <emmintrin.h>
#endif

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

string bodyName(int body, int numUserBodies, BodyParticles particles) {
    if (body < numUserBodies)
        return "rigid body "+std::to_string(body);
    return "free particle "+std::to_string(particles[0]);
}

/**
 * Write v to p with non-temporal stores where the processor has them (x86-64: movnti, one per
 * double, so a Vec3 needs no alignment beyond its own): consecutive particles fill whole cache
 * lines in the processor's write-combining buffers, which go to memory without being read first.
 */
inline void storeStreaming(Vec3& p, const Vec3& v) {
#if defined(__x86_64__) || defined(_M_X64)
    for (int k = 0; k < 3; k++) {
        double x = v[k];
        long long bits;
        std::memcpy(&bits, &x, sizeof(bits));
        _mm_stream_si64(reinterpret_cast<long long*>(&p[k]), bits);
    }
#else
    p = v;
#endif
}

/** Relative size below which a principal moment counts as zero (a linear or point body). */
const double ZeroMomentTolerance = 1e-10;

} // namespace

vector<int> BodyType::getActiveCoordinates() const {
    vector<int> active;
    for (int i = 0; i < getNumDegreesOfFreedom(); i++)
        active.push_back(activeCoordinate(numRotations, i));
    return active;
}

RigidBodyModel::RigidBodyModel(const System& system, const RigidBodyDescription& description) : integratorName(description.integratorName) {
    int numParticles = system.getNumParticles();
    numUserBodies = description.bodies.size();
    particleBody.assign(numParticles, -1);
    particleMass.resize(numParticles);
    for (int i = 0; i < numParticles; i++)
        particleMass[i] = system.getParticleMass(i);

    // User bodies: indices in range, no particle in two bodies, some mass.
    for (int b = 0; b < numUserBodies; b++) {
        const vector<int>& particles = description.bodies[b].particles;
        double mass = 0;
        for (int p : particles) {
            if (p < 0 || p >= numParticles)
                throw OpenMMException(integratorName+": rigid body "+std::to_string(b)+" contains particle "+std::to_string(p)+
                        ", but the System has only "+std::to_string(numParticles)+" particles");
            if (particleBody[p] == b)
                throw OpenMMException(integratorName+": rigid body "+std::to_string(b)+" lists particle "+std::to_string(p)+" twice");
            if (particleBody[p] != -1)
                throw OpenMMException(integratorName+": particle "+std::to_string(p)+" is in rigid body "+std::to_string(particleBody[p])+
                        " and in rigid body "+std::to_string(b)+"; a particle can belong to one body only");
            particleBody[p] = b;
            mass += particleMass[p];
        }
        if (!(mass > 0))
            throw OpenMMException(integratorName+": rigid body "+std::to_string(b)+" has no particle with mass; a body needs mass to move (massless sites must ride on a body that has mass)");
        bodyParticles.add(particles);
    }

    // A virtual site in a body rides on it: OpenMM defines it from its parents and hands its force
    // to them, so the parents must move with the site, in the same body, which then places all of
    // them. Only sites outside bodies are left to OpenMM to place after a step.
    particleIsVirtualSite.assign(numParticles, 0);
    sitesOutsideBodies = false;
    for (int p = 0; p < numParticles; p++) {
        if (!system.isVirtualSite(p))
            continue;
        particleIsVirtualSite[p] = 1;
        int b = particleBody[p];
        if (b == -1) {
            sitesOutsideBodies = true;
            continue;
        }
        const VirtualSite& site = system.getVirtualSite(p);
        for (int i = 0; i < site.getNumParticles(); i++)
            if (particleBody[site.getParticle(i)] != b)
                throw OpenMMException(integratorName+": particle "+std::to_string(p)+" in rigid body "+std::to_string(b)+" is a virtual site whose parent particle "+
                        std::to_string(site.getParticle(i))+" is "+(particleBody[site.getParticle(i)] == -1 ? string("in no rigid body") :
                        "in rigid body "+std::to_string(particleBody[site.getParticle(i)]))+". A body can carry a virtual site only together with all its parents: "
                        "put them in the same body, or leave the site out of every body");
    }
    exactShapes.reset(new ExactBodyShapes(system, bodyParticles, integratorName));

    // Free particles with mass move as single-particle bodies; massless ones stay where they are.
    for (int p = 0; p < numParticles; p++)
        if (particleBody[p] == -1 && particleMass[p] != 0) {
            particleBody[p] = bodyParticles.size();
            bodyParticles.add({p});
        }

    // Forces that move particles or set velocities behind the integrator's back would be undone by
    // the next step, which places particles from the body states.
    for (int i = 0; i < system.getNumForces(); i++) {
        const Force& force = system.getForce(i);
        if (dynamic_cast<const MonteCarloBarostat*>(&force) != NULL || dynamic_cast<const MonteCarloAnisotropicBarostat*>(&force) != NULL ||
                dynamic_cast<const MonteCarloMembraneBarostat*>(&force) != NULL || dynamic_cast<const MonteCarloFlexibleBarostat*>(&force) != NULL)
            throw OpenMMException(integratorName+": the System has a Monte Carlo barostat (force "+std::to_string(i)+"); barostats move particles "
                    "themselves, which rigid bodies cannot follow yet. Remove it and run at constant volume");
        if (dynamic_cast<const AndersenThermostat*>(&force) != NULL)
            throw OpenMMException(integratorName+": the System has an AndersenThermostat (force "+std::to_string(i)+"); the integrator is "
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
        throw OpenMMException(integratorName+": constraint "+std::to_string(i)+" between particles "+std::to_string(p1)+" and "+std::to_string(p2)+
                " does not lie inside one rigid body; rigid bodies replace constraints, so put both particles in the same body or remove the constraint");
    }

    // Explicit resistance tensors of user bodies.
    explicitTensor.resize(numUserBodies);
    explicitOrigin.resize(numUserBodies);
    explicitReference.resize(numUserBodies);
    for (int b = 0; b < numUserBodies; b++) {
        explicitTensor[b] = description.bodies[b].resistance;
        explicitOrigin[b] = description.bodies[b].resistanceOrigin;
        explicitReference[b] = description.bodies[b].resistanceReference;
    }
    explicitBlobs.resize(numUserBodies);
    for (int b = 0; b < numUserBodies; b++) {
        const RigidBodyDescription::Body& body = description.bodies[b];
        explicitBlobs[b].blobPositions = body.blobPositions;
        explicitBlobs[b].blobRadii = body.blobRadii;
        explicitBlobs[b].blobReference = body.blobReference;
    }

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
    for (auto& r : description.particleRadii) {
        if (r.first >= numParticles)
            throw OpenMMException(integratorName+": a radius was set for particle "+std::to_string(r.first)+", but the System has only "+std::to_string(numParticles)+" particles");
        particleRadius[r.first] = r.second;
        hasRadius[r.first] = true;
    }
    for (int b = 0; b < getNumBodies(); b++) {
        if (b < numUserBodies && !explicitTensor[b].empty())
            continue;
        for (int p : bodyParticles[b])
            if (particleMass[p] != 0 && !hasRadius[p])
                throw OpenMMException(integratorName+": particle "+std::to_string(p)+" ("+bodyName(b, numUserBodies, bodyParticles[b])+
                        ") has no hydrodynamic radius: it has no Lennard-Jones sigma with nonzero epsilon in a NonbondedForce. Call setParticleRadius("+
                        std::to_string(p)+", radius), or give the body an explicit tensor with setBodyResistance()");
    }
}

RigidBodyModel::~RigidBodyModel() {
}

vector<Vec3> RigidBodyModel::unwrappedOffsets(int body, const vector<Vec3>& positions, const Vec3* box, Vec3& centre) const {
    // Every particle is taken at its periodic image nearest the body's first particle, so that a
    // body split across the box by wrapping comes back whole.
    BodyParticles particles = bodyParticles[body];
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
                throw OpenMMException(integratorName+": "+bodyName(body, numUserBodies, particles)+" is wider than half the periodic box: particle "+
                        std::to_string(particles[i])+" is "+str(dist)+" nm from particle "+std::to_string(particles[0])+" but half the box is "+str(halfWidth)+
                        " nm. Use a larger box");
        }
        rel[i] = d;
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

bool RigidBodyModel::matchType(int type, const vector<Vec3>& offsets, double rotation[3][3], double& deviation, int& worst) const {
    // The rotation A (body frame to lab) that best places the type's shape on the body; Q = A^T.
    Eigen::Matrix3d a;
    deviation = fitRotation(types[type].coords, offsets, a, worst);
    fromMatrix3(a.transpose(), rotation);
    return deviation <= GeometryTolerance;
}

Eigen::Matrix3d RigidBodyModel::fitGivenReference(int body, const vector<Vec3>& reference, const vector<Vec3>& offsets, const string& given,
                                                  const string& placedFor, Vec3& referenceCentre) const {
    BodyParticles particles = bodyParticles[body];
    referenceCentre = Vec3();
    double mass = 0;
    for (int i = 0; i < (int) particles.size(); i++) {
        referenceCentre += reference[i]*particleMass[particles[i]];
        mass += particleMass[particles[i]];
    }
    referenceCentre /= mass;
    vector<Vec3> referenceOffsets;
    for (const Vec3& r : reference)
        referenceOffsets.push_back(r-referenceCentre);
    Eigen::Matrix3d toLab;
    int worst;
    double deviation = fitRotation(referenceOffsets, offsets, toLab, worst);
    if (deviation > GeometryTolerance)
        throw OpenMMException(integratorName+": the reference positions given with "+given+" of rigid body "+std::to_string(body)+
                " do not match its shape: particle "+std::to_string(particles[worst])+" is "+str(deviation)+" nm from its place after the best rigid "
                "motion (tolerance "+str(GeometryTolerance)+" nm). Pass the positions of the body's particles "+placedFor+", in the order of addRigidBody()");
    return toLab;
}

void RigidBodyModel::explicitBodyFrameBlobs(int body, const vector<Vec3>& offsets, const Eigen::Matrix3d& rotation, vector<Vec3>& coords) const {
    // Like an explicit tensor, the blobs belong to the shape at the positions they came with.
    const RigidBodyDescription::Body& given = explicitBlobs[body];
    Vec3 referenceCentre;
    Eigen::Matrix3d toLab = fitGivenReference(body, given.blobReference, offsets, "the blobs", "the blobs were placed around", referenceCentre);
    coords.clear();
    for (const Vec3& p : given.blobPositions)
        coords.push_back(toVec3(rotation*toLab*toEigen(p-referenceCentre)));
}

int RigidBodyModel::getFirstBodyOfType(int type) const {
    for (int b = 0; b < getNumBodies(); b++)
        if (bodyType[b] == type)
            return b;
    throw OpenMMException("RigidBodyModel: body type "+std::to_string(type)+" has no bodies");
}

string RigidBodyModel::getBodyName(int body) const {
    return bodyName(body, numUserBodies, bodyParticles[body]);
}

void RigidBodyModel::getTypeBlobs(int type, vector<Vec3>& coords, vector<double>& radii) const {
    const BodyType& t = types[type];
    int body = getFirstBodyOfType(type);
    string name = getBodyName(body);
    coords.clear();
    radii.clear();
    if (body < numUserBodies && !explicitBlobs[body].blobPositions.empty()) {
        explicitBodyFrameBlobs(body, t.coords, Eigen::Matrix3d::Identity(), coords);
        radii = explicitBlobs[body].blobRadii;
    }
    else {
        for (int i = 0; i < (int) t.coords.size(); i++)
            if (t.radii[i] > 0) {
                coords.push_back(t.coords[i]);
                radii.push_back(t.radii[i]);
            }
        if (coords.empty())
            throw OpenMMException(integratorName+": "+name+" has no hydrodynamic blobs for hydrodynamic interactions: none of its particles has a "
                    "radius. Give it blobs with setBodyBlobs(), or radii with setParticleRadius()");
    }
    // A body that does not turn about some axis cannot carry blobs that would need it to.
    for (const Vec3& b : coords) {
        double off = (t.numRotations == 0 ? std::sqrt(b.dot(b)) : t.numRotations == 2 ? std::sqrt(b[1]*b[1]+b[2]*b[2]) : 0.0);
        if (off > GeometryTolerance)
            throw OpenMMException(integratorName+": "+name+" has its mass "+(t.numRotations == 0 ? "at one point" : "on one line")+
                    ", so it cannot turn "+(t.numRotations == 0 ? "at all" : "about its axis")+", but one of its hydrodynamic blobs is "+str(off)+
                    " nm off that "+(t.numRotations == 0 ? "point" : "line")+". Place its blobs on it, or give the body mass off it so that it rotates");
    }
}

Matrix6 RigidBodyModel::bodyFrameResistance(int body, const vector<Vec3>& offsets, const double rotation[3][3]) const {
    Eigen::Matrix3d q = toMatrix3(rotation);
    BodyParticles particles = bodyParticles[body];
    if (body < numUserBodies && !explicitTensor[body].empty()) {
        // The tensor belongs to the body's shape at the reference positions it came with: about
        // their centre of mass, then turned from their frame into the body frame.
        Vec3 referenceCentre;
        Eigen::Matrix3d toLab = fitGivenReference(body, explicitReference[body], offsets, "the resistance tensor", "the tensor was computed for", referenceCentre);
        ResistanceTensor given = ResistanceTensor::fromMatrix(explicitTensor[body], explicitOrigin[body]);
        Matrix6 xi = Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> >(given.getMatrix(referenceCentre).data());
        return rotate(xi, q*toLab);
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
        throw OpenMMException(integratorName+": "+bodyName(body, numUserBodies, particles)+" has no particle with a hydrodynamic radius; "
                "set radii with setParticleRadius() or give it an explicit tensor");
    ResistanceTensor model = ResistanceTensor::beads(beads, radii, ResistanceTensor::unionVolume(beads, radii));
    return Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> >(model.getMatrix(Vec3()).data());
}

void RigidBodyModel::classifyFriction(BodyType& t, const string& name) const {
    vector<int> active = t.getActiveCoordinates();
    int dof = active.size();
    Eigen::MatrixXd xi(dof, dof);
    for (int i = 0; i < dof; i++)
        for (int j = 0; j < dof; j++)
            xi(i, j) = t.resistance(active[i], active[j]);
    Eigen::LLT<Eigen::MatrixXd> llt(xi);
    if (llt.info() != Eigen::Success || !xi.allFinite())
        throw OpenMMException(integratorName+": the friction of "+name+" is not positive definite in the motions it can make; "
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
}

int RigidBodyModel::createType(int body, const vector<Vec3>& offsets, double rotation[3][3]) {
    BodyParticles particles = bodyParticles[body];
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
        t.isVirtualSite.push_back(particleIsVirtualSite[particles[i]]);
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
                    throw OpenMMException(integratorName+": "+name+" has its mass "+(t.numRotations == 0 ? "at one point" : "on one line")+
                            ", but massless particle "+std::to_string(particles[i])+" is "+str(off)+" nm off it, so the body cannot carry it. "
                            "Give that particle mass or move it onto the "+(t.numRotations == 0 ? "point" : "line"));
            }
        if (t.numRotations == 2)
            b[1] = b[2] = 0;
        else if (t.numRotations == 0)
            b.setZero();
        t.coords.push_back(toVec3(b));
    }
    t.diameter = shapeDiameter(t.coords);

    // Friction per unit viscosity in the body frame about the centre of mass.
    t.explicitResistance = (body < numUserBodies && !explicitTensor[body].empty());
    t.resistance = bodyFrameResistance(body, offsets, rotation);
    classifyFriction(t, name);
    types.push_back(t);
    return types.size()-1;
}

int RigidBodyModel::findOrCreateType(int body, const vector<Vec3>& offsets, double rotation[3][3]) {
    // Bodies with the same masses, radii and friction model, whose shapes agree up to a rotation,
    // share a type (and take its exact shape).
    BodyParticles particles = bodyParticles[body];
    vector<double> signature;
    signature.push_back(particles.size());
    for (int p : particles) {
        signature.push_back(particleMass[p]);
        signature.push_back(particleRadius[p]);
        signature.push_back(particleIsVirtualSite[p]);
    }
    bool isExplicit = (body < numUserBodies && !explicitTensor[body].empty());
    signature.push_back(isExplicit ? 1 : 0);
    bool hasBlobs = (body < numUserBodies && !explicitBlobs[body].blobPositions.empty());
    if (hasBlobs) {
        signature.push_back(explicitBlobs[body].blobRadii.size());
        for (double r : explicitBlobs[body].blobRadii)
            signature.push_back(r);
    }
    auto range = typesBySignature.equal_range(signature);
    for (auto it = range.first; it != range.second; ++it) {
        double deviation;
        int worst;
        if (!matchType(it->second, offsets, rotation, deviation, worst))
            continue;
        if (isExplicit) {
            Matrix6 xi = bodyFrameResistance(body, offsets, rotation);
            const Matrix6& typeXi = types[it->second].resistance;
            if ((xi-typeXi).cwiseAbs().maxCoeff() > 1e-8*typeXi.cwiseAbs().maxCoeff())
                continue;
        }
        if (hasBlobs) {
            // Identical bodies with their blobs in other places do not share a type.
            vector<Vec3> mine, theirs;
            vector<double> theirRadii;
            explicitBodyFrameBlobs(body, offsets, toMatrix3(rotation), mine);
            getTypeBlobs(it->second, theirs, theirRadii);
            bool same = true;
            for (int k = 0; k < (int) mine.size(); k++)
                same = same && std::sqrt((mine[k]-theirs[k]).dot(mine[k]-theirs[k])) <= GeometryTolerance;
            if (!same)
                continue;
        }
        return it->second;
    }
    int type = createType(body, offsets, rotation);
    typesBySignature.insert(std::make_pair(signature, type));
    return type;
}

void RigidBodyModel::checkBodiesWhole(const vector<Vec3>& positions, const Vec3* box) const {
    // Two particles more than half a box apart as given are nearest images at another distance: a
    // body that long would silently take another shape (a 1.2 nm dimer in a 2 nm box would become
    // 0.8 nm long), and a body wrapped into the box particle by particle looks the same. Which one
    // it is cannot be told, so the positions that define the shapes must have each body whole.
    double halfWidth = 0.5*std::min(box[0][0], std::min(box[1][1], box[2][2]));
    for (int b = 0; b < getNumBodies(); b++) {
        BodyParticles particles = bodyParticles[b];
        Vec3 first = positions[particles[0]];
        for (int i = 1; i < (int) particles.size(); i++) {
            Vec3 given = positions[particles[i]]-first, nearest = given;
            nearest -= box[2]*std::round(nearest[2]/box[2][2]);
            nearest -= box[1]*std::round(nearest[1]/box[1][1]);
            nearest -= box[0]*std::round(nearest[0]/box[0][0]);
            Vec3 shift = given-nearest;
            if (shift.dot(shift) > 1e-12)
                throw OpenMMException(integratorName+": "+bodyName(b, numUserBodies, particles)+" is longer than half the periodic box in the "
                        "positions first set on the Context: particles "+std::to_string(particles[0])+" and "+std::to_string(particles[i])+" are "+
                        str(std::sqrt(given.dot(given)))+" nm apart, but half the box is "+str(halfWidth)+" nm (their nearest images are "+
                        str(std::sqrt(nearest.dot(nearest)))+" nm apart, which would give the body another shape). Use a larger box; or, if the "
                        "body was wrapped into the box particle by particle, set the first positions with every body whole (later ones may be wrapped)");
        }
    }
}

vector<BodyState> RigidBodyModel::fitStates(const vector<Vec3>& positions, const vector<Vec3>& velocities, const Vec3* box) {
    bool firstBuild = types.empty();
    for (int b = 0; b < getNumBodies(); b++)
        for (int p : bodyParticles[b])
            if (!std::isfinite(positions[p][0]) || !std::isfinite(positions[p][1]) || !std::isfinite(positions[p][2]))
                throw OpenMMException(integratorName+": particle "+std::to_string(p)+" has a position that is not finite");
    if (firstBuild && box != NULL)
        checkBodiesWhole(positions, box);
    vector<Vec3> exact;
    if (firstBuild && exactShapes->isNeeded()) {
        // The types' shapes obey the System's constraints and virtual sites exactly.
        exact = positions;
        for (int b = 0; b < numUserBodies; b++) {
            Vec3 centre;
            vector<Vec3> offsets = unwrappedOffsets(b, positions, box, centre);
            for (int i = 0; i < (int) offsets.size(); i++)
                exact[bodyParticles[b][i]] = centre+offsets[i];
        }
        exactShapes->apply(exact);
    }
    const vector<Vec3>& shapes = (exact.empty() ? positions : exact);
    if (firstBuild)
        bodyType.resize(getNumBodies());
    double halfWidth = (box == NULL ? 0.0 : 0.5*std::min(box[0][0], std::min(box[1][1], box[2][2])));
    vector<BodyState> states(getNumBodies());
    for (int b = 0; b < getNumBodies(); b++) {
        BodyParticles particles = bodyParticles[b];
        BodyState& s = states[b];
        vector<Vec3> offsets = unwrappedOffsets(b, shapes, box, s.position);
        if (firstBuild)
            bodyType[b] = findOrCreateType(b, offsets, s.rotation);
        else {
            double deviation;
            int worst;
            if (!matchType(bodyType[b], offsets, s.rotation, deviation, worst))
                throw OpenMMException(integratorName+": the positions deform "+bodyName(b, numUserBodies, particles)+": particle "+
                        std::to_string(particles[worst])+" is "+str(deviation)+" nm from its place in the rigid body (tolerance "+str(GeometryTolerance)+
                        " nm). Bodies keep the shape of the positions first set on the Context; to change shapes, call Context.reinitialize()");
        }
        const BodyType& t = types[bodyType[b]];
        // Particles each within half a box of the first can still span more than half a box
        // together, and then which images belong together is ambiguous.
        if (box != NULL && t.diameter >= halfWidth*(1-1e-12))
            throw OpenMMException(integratorName+": "+bodyName(b, numUserBodies, particles)+" is wider than half the periodic box: two of its particles are "+
                    str(t.diameter)+" nm apart but half the box is "+str(halfWidth)+" nm. Use a larger box");
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
    for (int b = 0; b < getNumBodies(); b++)
        placeBodyParticles(b, states[b], positions, velocities);
}

void RigidBodyModel::placeBodyParticles(int body, const BodyState& s, vector<Vec3>& positions, vector<Vec3>& velocities, ParticleStores stores) const {
    const BodyType& t = types[bodyType[body]];
    BodyParticles particles = bodyParticles[body];
    Vec3 omega;  // body frame
    for (int k = 0; k < 3; k++)
        omega[k] = (t.rotates(k) ? s.angularMomentum[k]/t.inertia[k] : 0.0);
    const bool streaming = (stores == ParticleStores::Streaming);
    for (int i = 0; i < particles.size(); i++) {
        const Vec3& c = t.coords[i];
        // Lab-frame offset Q^T b and velocity Q^T (omega x b).
        Vec3 w = omega.cross(c);
        Vec3 offset, vel;
        for (int k = 0; k < 3; k++) {
            offset[k] = s.rotation[0][k]*c[0]+s.rotation[1][k]*c[1]+s.rotation[2][k]*c[2];
            vel[k] = s.rotation[0][k]*w[0]+s.rotation[1][k]*w[1]+s.rotation[2][k]*w[2];
        }
        if (streaming) {
            storeStreaming(positions[particles[i]], s.position+offset);
            storeStreaming(velocities[particles[i]], s.velocity+vel);
        }
        else {
            positions[particles[i]] = s.position+offset;
            velocities[particles[i]] = s.velocity+vel;
        }
    }
}

RigidBodyModel::ParticleStores RigidBodyModel::chooseParticleStores(long long cacheBytes) const {
    // Streaming stores fill whole lines only where consecutive bodies write consecutive particles;
    // count the places where the next particle written is not the next in memory.
    long long numParticles = 0, jumps = 0;
    int previous = -2;
    for (int b = 0; b < getNumBodies(); b++)
        for (int p : bodyParticles[b]) {
            numParticles++;
            jumps += (p != previous+1);
            previous = p;
        }
    if (jumps > numParticles/16)
        return ParticleStores::Cached;
    // Per body its state (position, velocity, angular momentum, rotation) and the start of its
    // particle list; per particle its position, velocity, force and index.
    long long touched = (long long) getNumBodies()*(sizeof(BodyState)+sizeof(int))+numParticles*(3*sizeof(Vec3)+sizeof(int));
    return (touched > cacheBytes ? ParticleStores::Streaming : ParticleStores::Cached);
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

void RigidBodyModel::clearTypes() {
    types.clear();
    bodyType.clear();
    typesBySignature.clear();
}
