// Body types and states as States and checkpoints carry them: writing them, reading them back and
// restoring the states into the model the integrator built (RigidBodyModel::restoreStates()).

#include "internal/RigidBodyModel.h"
#include "internal/RigidFit.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <istream>
#include <map>
#include <ostream>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::string;
using std::vector;

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
void readVector(std::istream& stream, vector<T>& values, const string& integrator) {
    int size;
    readValue(stream, size);
    if (!stream || size < 0 || size > (1<<28))
        throw OpenMMException(integrator+": the checkpoint is corrupt");
    values.resize(size);
    stream.read((char*) values.data(), size*sizeof(T));
}

/**
 * Relative difference below which a saved friction matrix is this model's, computed again in the
 * saved frame: rounding makes them differ by ~1e-15; a friction a user changed differs by far more.
 */
const double SameFrictionTolerance = 1e-10;

/** d moved to its nearest periodic image (box in OpenMM's reduced form). */
Vec3 nearestImage(Vec3 d, const Vec3* box) {
    d -= box[2]*std::round(d[2]/box[2][2]);
    d -= box[1]*std::round(d[1]/box[1][1]);
    d -= box[0]*std::round(d[0]/box[0][0]);
    return d;
}

} // namespace

void RigidBodyModel::writeTypes(std::ostream& stream) const {
    int numTypes = types.size();
    writeValue(stream, numTypes);
    for (const BodyType& t : types) {
        writeVector(stream, t.masses);
        writeVector(stream, t.radii);
        writeVector(stream, t.coords);
        writeVector(stream, t.isVirtualSite);
        writeValue(stream, t.mass);
        writeValue(stream, t.inertia);
        writeValue(stream, t.numRotations);
        writeValue(stream, t.explicitResistance);
        writeValue(stream, t.resistance);
        writeValue(stream, t.frictionClass);
    }
    writeVector(stream, bodyType);
}

void RigidBodyModel::readTypes(std::istream& stream, SavedBodies& saved) const {
    int numTypes;
    readValue(stream, numTypes);
    if (!stream || numTypes < 0 || numTypes > getNumBodies())
        throw OpenMMException(integratorName+": the checkpoint is corrupt or was written for another System: it has "+std::to_string(numTypes)+
                " body types for "+std::to_string(getNumBodies())+" bodies");
    saved.types.assign(numTypes, BodyType());
    for (BodyType& t : saved.types) {
        readVector(stream, t.masses, integratorName);
        readVector(stream, t.radii, integratorName);
        readVector(stream, t.coords, integratorName);
        readVector(stream, t.isVirtualSite, integratorName);
        readValue(stream, t.mass);
        readValue(stream, t.inertia);
        readValue(stream, t.numRotations);
        readValue(stream, t.explicitResistance);
        readValue(stream, t.resistance);
        readValue(stream, t.frictionClass);
    }
    readVector(stream, saved.bodyType, integratorName);
    if (!stream)
        throw OpenMMException(integratorName+": the checkpoint is truncated (it ends inside the rigid body types)");
}

void RigidBodyModel::writeTypes(SerializationNode& node) const {
    SerializationNode& typesNode = node.createChildNode("BodyTypes");
    for (const BodyType& t : types) {
        SerializationNode& n = typesNode.createChildNode("Type");
        n.setDoubleProperty("mass", t.mass).setIntProperty("numRotations", t.numRotations);
        n.setIntProperty("frictionClass", (int) t.frictionClass).setBoolProperty("explicitResistance", t.explicitResistance);
        n.setDoubleProperty("I0", t.inertia[0]).setDoubleProperty("I1", t.inertia[1]).setDoubleProperty("I2", t.inertia[2]);
        SerializationNode& xi = n.createChildNode("Resistance");
        for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++)
                xi.setDoubleProperty("x"+std::to_string(i)+std::to_string(j), t.resistance(i, j));
        for (int i = 0; i < (int) t.masses.size(); i++)
            n.createChildNode("Particle").setDoubleProperty("m", t.masses[i]).setDoubleProperty("r", t.radii[i]).setIntProperty("site", t.isVirtualSite[i])
                    .setDoubleProperty("x", t.coords[i][0]).setDoubleProperty("y", t.coords[i][1]).setDoubleProperty("z", t.coords[i][2]);
    }
    SerializationNode& assignment = node.createChildNode("BodyTypeOfBody");
    for (int type : bodyType)
        assignment.createChildNode("Body").setIntProperty("type", type);
}

void RigidBodyModel::readTypes(const SerializationNode& node, SavedBodies& saved) const {
    // The friction a State carries is read for completeness of the format, never used: the
    // integrator that reads the State defines the physics.
    saved.types.clear();
    saved.bodyType.clear();
    try {
        for (const SerializationNode& n : node.getChildNode("BodyTypes").getChildren()) {
            BodyType t;
            t.mass = n.getDoubleProperty("mass");
            t.numRotations = n.getIntProperty("numRotations");
            t.frictionClass = (FrictionClass) n.getIntProperty("frictionClass");
            t.explicitResistance = n.getBoolProperty("explicitResistance");
            t.inertia = Vec3(n.getDoubleProperty("I0"), n.getDoubleProperty("I1"), n.getDoubleProperty("I2"));
            const SerializationNode& xi = n.getChildNode("Resistance");
            for (int i = 0; i < 6; i++)
                for (int j = 0; j < 6; j++)
                    t.resistance(i, j) = xi.getDoubleProperty("x"+std::to_string(i)+std::to_string(j));
            for (const SerializationNode& p : n.getChildren())
                if (p.getName() == "Particle") {
                    t.masses.push_back(p.getDoubleProperty("m"));
                    t.radii.push_back(p.getDoubleProperty("r"));
                    t.isVirtualSite.push_back(p.getIntProperty("site"));
                    t.coords.push_back(Vec3(p.getDoubleProperty("x"), p.getDoubleProperty("y"), p.getDoubleProperty("z")));
                }
            saved.types.push_back(t);
        }
        for (const SerializationNode& b : node.getChildNode("BodyTypeOfBody").getChildren())
            saved.bodyType.push_back(b.getIntProperty("type"));
    }
    catch (const OpenMMException& e) {
        throw OpenMMException(integratorName+": the State's rigid body types are incomplete: "+e.what());
    }
}

void RigidBodyModel::checkSavedTypes(const SavedBodies& saved, const string& source) const {
    for (int t = 0; t < (int) saved.types.size(); t++) {
        const BodyType& type = saved.types[t];
        size_t n = type.masses.size();
        bool finite = std::isfinite(type.mass) && type.resistance.allFinite();
        for (int k = 0; k < 3; k++)
            finite = finite && std::isfinite(type.inertia[k]) && type.inertia[k] >= 0;
        for (size_t i = 0; i < type.coords.size(); i++)
            finite = finite && std::isfinite(type.coords[i][0]) && std::isfinite(type.coords[i][1]) && std::isfinite(type.coords[i][2]);
        if (n == 0 || type.radii.size() != n || type.coords.size() != n || type.isVirtualSite.size() != n || !finite || !(type.mass > 0) ||
                (type.numRotations != 0 && type.numRotations != 2 && type.numRotations != 3) ||
                (int) type.frictionClass < 0 || (int) type.frictionClass > (int) FrictionClass::Coupled)
            throw OpenMMException(integratorName+": the "+source+"'s rigid body type "+std::to_string(t)+" is corrupt (sizes, numbers of "
                    "rotations, friction class or values out of range)");
    }
    for (int b = 0; b < (int) saved.bodyType.size(); b++)
        if (saved.bodyType[b] < 0 || saved.bodyType[b] >= (int) saved.types.size())
            throw OpenMMException(integratorName+": the "+source+"'s body "+std::to_string(b)+" has body type "+std::to_string(saved.bodyType[b])+
                    ", but there are "+std::to_string(saved.types.size()));
    for (int b = 0; b < (int) saved.states.size(); b++) {
        const BodyState& s = saved.states[b];
        bool good = true;
        for (int k = 0; k < 3; k++)
            good = good && std::isfinite(s.position[k]) && std::isfinite(s.velocity[k]) && std::isfinite(s.angularMomentum[k]);
        Eigen::Matrix3d q = toMatrix3(s.rotation);
        good = good && q.allFinite() && (q*q.transpose()-Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6;
        if (!good)
            throw OpenMMException(integratorName+": the "+source+"'s state of body "+std::to_string(b)+" is corrupt (a value is not finite or "
                    "its rotation is not orthonormal)");
    }
}

bool RigidBodyModel::savedBodiesMatch(const SavedBodies& saved) const {
    if ((int) saved.bodyType.size() != getNumBodies() || (int) saved.states.size() != getNumBodies())
        return false;
    for (int b = 0; b < getNumBodies(); b++) {
        const BodyType& type = saved.types[saved.bodyType[b]];
        if ((int) type.masses.size() != bodyParticles[b].size())
            return false;
        for (int i = 0; i < (int) bodyParticles[b].size(); i++) {
            int p = bodyParticles[b][i];
            if (type.masses[i] != particleMass[p] || type.isVirtualSite[i] != particleIsVirtualSite[p])
                return false;
        }
    }
    return true;
}

bool RigidBodyModel::fitSavedFrames(const SavedBodies& saved, std::map<std::pair<int, int>, Eigen::Matrix3d>& frameChange) const {
    for (int b = 0; b < getNumBodies(); b++) {
        std::pair<int, int> key(saved.bodyType[b], bodyType[b]);
        if (frameChange.count(key) != 0)
            continue;
        const vector<Vec3>& from = saved.types[key.first].coords;
        const vector<Vec3>& to = types[key.second].coords;
        Eigen::Matrix3d p = Eigen::Matrix3d::Identity();
        int worst;
        if (from != to && fitRotation(from, to, p, worst) > GeometryTolerance)
            return false;
        frameChange[key] = p;
    }
    return true;
}

bool RigidBodyModel::restoreStates(const SavedBodies& saved, const vector<Vec3>& positions, const Vec3* box, vector<BodyState>& states,
                                   bool& typesChanged) {
    typesChanged = false;
    std::map<std::pair<int, int>, Eigen::Matrix3d> frameChange;
    if (!savedBodiesMatch(saved) || !fitSavedFrames(saved, frameChange))
        return false;
    // A body at Q_saved is at Q_here = P Q_saved, and its body-frame angular momentum is P j_saved.
    states.resize(getNumBodies());
    for (int b = 0; b < getNumBodies(); b++) {
        const Eigen::Matrix3d& p = frameChange[std::make_pair(saved.bodyType[b], bodyType[b])];
        const BodyState& from = saved.states[b];
        const BodyType& type = types[bodyType[b]];
        BodyState& s = states[b];
        s.position = from.position;
        s.velocity = from.velocity;
        fromMatrix3(type.numRotations == 0 ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(p*toMatrix3(from.rotation)), s.rotation);
        Vec3 j = ResistanceMath::toVec3(p*ResistanceMath::toEigen(from.angularMomentum));
        for (int k = 0; k < 3; k++)
            s.angularMomentum[k] = (type.rotates(k) ? j[k] : 0.0);
    }
    if (!placedAt(states, positions, box))
        return false;
    typesChanged = adoptSavedFrames(saved, states);
    return true;
}

bool RigidBodyModel::adoptSavedFrames(const SavedBodies& saved, vector<BodyState>& states) {
    // The one saved type of each type's bodies: -2 none seen yet, -1 several.
    vector<int> savedType(types.size(), -2);
    for (int b = 0; b < getNumBodies(); b++) {
        int& s = savedType[bodyType[b]];
        s = (s == -2 || s == saved.bodyType[b] ? saved.bodyType[b] : -1);
    }
    bool changed = false;
    for (int t = 0; t < (int) types.size(); t++) {
        int s = savedType[t];
        if (s < 0 || saved.types[s].numRotations != types[t].numRotations) {
            savedType[t] = -1;
            continue;
        }
        const BodyType& from = saved.types[s];
        BodyType& type = types[t];
        if (from.coords == type.coords && from.inertia == type.inertia)
            continue;
        type.coords = from.coords;
        type.inertia = from.inertia;
        type.diameter = shapeDiameter(type.coords);
        // This model's friction computed again in the saved frame, from the saved shape: the default
        // model's volume correction integrates on a grid along the frame's axes, so the friction of
        // the same body computed in a frame fitted the other way round (a fresh Context fits its
        // bodies to the checkpoint's particles) differs by ~1e-7, and turning it into the saved frame
        // continued the run with other friction, and with another friction class other random numbers.
        // Where it is the saved one but for rounding, the saved one as it is, so that the run
        // continues bit for bit; where it differs (radii or a tensor changed), this model's.
        const double identity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        Matrix6 here = bodyFrameResistance(getFirstBodyOfType(t), from.coords, identity);
        if ((here-from.resistance).cwiseAbs().maxCoeff() <= SameFrictionTolerance*here.cwiseAbs().maxCoeff()) {
            type.resistance = from.resistance;
            type.frictionClass = from.frictionClass;
        }
        else {
            type.resistance = here;
            classifyFriction(type, getBodyName(getFirstBodyOfType(t)));
        }
        changed = true;
    }
    for (int b = 0; b < getNumBodies(); b++)
        if (savedType[bodyType[b]] >= 0)
            states[b] = saved.states[b];
    if (changed)
        typesBySignature.clear();
    return changed;
}

bool RigidBodyModel::placedAt(const vector<BodyState>& states, const vector<Vec3>& positions, const Vec3* box) const {
    // Saved states restored into other particles (bodies, or a body's particles, listed in another
    // order than where they were saved) would put them where other particles were saved.
    vector<Vec3> placed(positions.size()), velocities(positions.size());
    for (int b = 0; b < getNumBodies(); b++) {
        placeBodyParticles(b, states[b], placed, velocities);
        for (int p : bodyParticles[b]) {
            Vec3 d = placed[p]-positions[p];
            if (box != NULL)
                d = nearestImage(d, box);
            if (!(std::sqrt(d.dot(d)) <= GeometryTolerance))
                return false;
        }
    }
    return true;
}
