#ifndef RIGID_LANGEVIN_BODY_PARTICLE_LISTS_H_
#define RIGID_LANGEVIN_BODY_PARTICLE_LISTS_H_

#include <vector>

namespace RigidLangevinPlugin {

/** The particles of one body in the body's order: a view into BodyParticleLists. */
class BodyParticles {
public:
    BodyParticles(const int* first, int count) : first(first), count(count) {
    }
    const int* begin() const {
        return first;
    }
    const int* end() const {
        return first+count;
    }
    int size() const {
        return count;
    }
    int operator[](int i) const {
        return first[i];
    }
private:
    const int* first;
    int count;
};

/**
 * Every body's particles in one array, body after body, so that a step sweeping the bodies reads
 * their particle indices as one stream rather than from an allocation per body (whose header and
 * block a vector per body would add to every body-step's traffic).
 */
class BodyParticleLists {
public:
    /** Append a body with these particles. */
    void add(const std::vector<int>& particles) {
        index.insert(index.end(), particles.begin(), particles.end());
        start.push_back(index.size());
    }
    /** The number of bodies. */
    int size() const {
        return start.size()-1;
    }
    BodyParticles operator[](int body) const {
        return BodyParticles(index.data()+start[body], start[body+1]-start[body]);
    }
private:
    std::vector<int> start{0};  // body b's particles are index[start[b]] to index[start[b+1]-1]
    std::vector<int> index;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BODY_PARTICLE_LISTS_H_*/
