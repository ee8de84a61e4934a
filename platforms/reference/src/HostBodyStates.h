#ifndef HOST_BODY_STATES_H_
#define HOST_BODY_STATES_H_

#include "internal/RigidBodyModel.h"
#include "openmm/Vec3.h"
#include <array>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The states of all bodies as a structure of arrays, one array per quantity, so that a thread
 * sweeping a range of bodies reads each quantity contiguously. A body is loaded into a BodyState
 * to be advanced by the shared equations of motion (BodyDynamics.h) and stored back.
 */
struct HostBodyStates {
    std::vector<OpenMM::Vec3> position, velocity, angularMomentum;
    std::vector<std::array<double, 9> > rotation;  ///< Q row by row

    void resize(int numBodies) {
        position.resize(numBodies);
        velocity.resize(numBodies);
        angularMomentum.resize(numBodies);
        rotation.resize(numBodies);
    }
    int size() const {
        return position.size();
    }
    BodyState load(int body) const {
        BodyState s;
        s.position = position[body];
        s.velocity = velocity[body];
        s.angularMomentum = angularMomentum[body];
        const std::array<double, 9>& q = rotation[body];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                s.rotation[i][j] = q[3*i+j];
        return s;
    }
    /**
     * Load a body that does not rotate without reading what it cannot change: its angular momentum
     * is zero and its rotation the identity (RigidBodyModel gives such a body the identity frame and
     * no off-centre particle, and it never turns). Store it back with storePoint().
     */
    BodyState loadPoint(int body) const {
        BodyState s;
        s.position = position[body];
        s.velocity = velocity[body];
        s.angularMomentum = OpenMM::Vec3();
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                s.rotation[i][j] = (i == j ? 1.0 : 0.0);
        return s;
    }
    void storePoint(int body, const BodyState& s) {
        position[body] = s.position;
        velocity[body] = s.velocity;
    }
    void store(int body, const BodyState& s) {
        position[body] = s.position;
        velocity[body] = s.velocity;
        angularMomentum[body] = s.angularMomentum;
        std::array<double, 9>& q = rotation[body];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                q[3*i+j] = s.rotation[i][j];
    }
};

} // namespace RigidLangevinPlugin

#endif /*HOST_BODY_STATES_H_*/
