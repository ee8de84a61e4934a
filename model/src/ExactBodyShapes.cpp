#include "internal/ExactBodyShapes.h"
#include "openmm/Context.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/VirtualSite.h"
#include <algorithm>
#include <cmath>
#include <map>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

namespace {

/** Relative accuracy of the constrained distances (CCMA; SETTLE is exact). */
const double ConstraintTolerance = 1e-13;

/** Passes of the constraint algorithm at most (each squares the error of the last). */
const int MaxPasses = 10;

/** The same virtual site with its parents renumbered by index; NULL for kinds a body cannot carry. */
VirtualSite* renumbered(const VirtualSite& site, const std::map<int, int>& index) {
    auto at = [&] (int i) {
        return index.at(site.getParticle(i));
    };
    if (auto s = dynamic_cast<const TwoParticleAverageSite*>(&site))
        return new TwoParticleAverageSite(at(0), at(1), s->getWeight(0), s->getWeight(1));
    if (auto s = dynamic_cast<const ThreeParticleAverageSite*>(&site))
        return new ThreeParticleAverageSite(at(0), at(1), at(2), s->getWeight(0), s->getWeight(1), s->getWeight(2));
    if (auto s = dynamic_cast<const OutOfPlaneSite*>(&site))
        return new OutOfPlaneSite(at(0), at(1), at(2), s->getWeight12(), s->getWeight13(), s->getWeightCross());
    if (auto s = dynamic_cast<const LocalCoordinatesSite*>(&site)) {
        vector<int> parents(site.getNumParticles());
        for (int i = 0; i < site.getNumParticles(); i++)
            parents[i] = at(i);
        vector<double> origin, x, y;
        s->getOriginWeights(origin);
        s->getXWeights(x);
        s->getYWeights(y);
        return new LocalCoordinatesSite(parents, origin, x, y, s->getLocalPosition());
    }
    return NULL;  // SymmetrySite: a rotated image of its parent does not move with it rigidly
}

} // namespace

ExactBodyShapes::ExactBodyShapes(const System& system, const BodyParticleLists& bodyParticles, const std::string& integrator) {
    vector<int> particleBody(system.getNumParticles(), -1);
    for (int b = 0; b < (int) bodyParticles.size(); b++)
        for (int p : bodyParticles[b])
            particleBody[p] = b;
    vector<bool> needed(bodyParticles.size(), false);
    for (int i = 0; i < system.getNumConstraints(); i++) {
        int p1, p2;
        double distance;
        system.getConstraintParameters(i, p1, p2, distance);
        if (particleBody[p1] != -1 && particleBody[p1] == particleBody[p2])
            needed[particleBody[p1]] = true;
    }
    for (int p = 0; p < system.getNumParticles(); p++)
        if (particleBody[p] != -1 && system.isVirtualSite(p))
            needed[particleBody[p]] = true;
    std::map<int, int> index;
    for (int b = 0; b < (int) bodyParticles.size(); b++)
        if (needed[b])
            for (int p : bodyParticles[b]) {
                index[p] = particles.size();
                particles.push_back(p);
            }
    if (particles.empty())
        return;
    shapes.reset(new System());
    for (int p : particles)
        shapes->addParticle(system.getParticleMass(p));
    for (int i = 0; i < system.getNumConstraints(); i++) {
        int p1, p2;
        double distance;
        system.getConstraintParameters(i, p1, p2, distance);
        if (index.count(p1) != 0 && particleBody[p1] == particleBody[p2])
            shapes->addConstraint(index[p1], index[p2], distance);
    }
    for (int p : particles)
        if (system.isVirtualSite(p)) {
            VirtualSite* site = renumbered(system.getVirtualSite(p), index);
            if (site == NULL)
                throw OpenMMException(integrator+": particle "+std::to_string(p)+" of rigid body "+std::to_string(particleBody[p])+
                        " is a SymmetrySite, which does not move rigidly with its parent; take it out of the body");
            shapes->setVirtualSite(index[p], site);
        }
}

ExactBodyShapes::~ExactBodyShapes() {
}

void ExactBodyShapes::apply(vector<Vec3>& positions) const {
    if (!isNeeded())
        return;
    vector<Vec3> local(particles.size());
    for (int i = 0; i < (int) particles.size(); i++)
        local[i] = positions[particles[i]];
    VerletIntegrator integrator(0.001);
    Context context(*shapes, integrator, Platform::getPlatformByName("Reference"));
    integrator.setConstraintTolerance(ConstraintTolerance);
    context.setPositions(local);
    // SETTLE and CCMA take the positions they start from as the reference geometry: each pass
    // starts from a better one, and the error shrinks quadratically. Passes until round-off.
    for (int pass = 0; pass < MaxPasses; pass++) {
        context.applyConstraints(ConstraintTolerance);
        local = context.getState(State::Positions).getPositions();
        double worst = 0;
        for (int i = 0; i < shapes->getNumConstraints(); i++) {
            int p1, p2;
            double distance;
            shapes->getConstraintParameters(i, p1, p2, distance);
            Vec3 d = local[p1]-local[p2];
            worst = std::max(worst, std::abs(std::sqrt(d.dot(d))-distance)/distance);
        }
        if (worst <= ConstraintTolerance)
            break;
    }
    context.computeVirtualSites();
    local = context.getState(State::Positions).getPositions();
    for (int i = 0; i < (int) particles.size(); i++)
        positions[particles[i]] = local[i];
}
