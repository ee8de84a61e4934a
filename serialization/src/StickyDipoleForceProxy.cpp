#include "StickyDipoleForceProxy.h"
#include "StickyDipoleForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/serialization/SerializationNode.h"
#include <memory>

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

const int Version = 1;

} // namespace

StickyDipoleForceProxy::StickyDipoleForceProxy() : SerializationProxy("StickyDipoleForce") {
}

void StickyDipoleForceProxy::serialize(const void* object, SerializationNode& node) const {
    node.setIntProperty("version", Version);
    const StickyDipoleForce& force = *reinterpret_cast<const StickyDipoleForce*>(object);
    node.setIntProperty("forceGroup", force.getForceGroup());
    node.setStringProperty("name", force.getName());
    node.setIntProperty("method", force.getNonbondedMethod());
    node.setDoubleProperty("cutoff", force.getCutoffDistance());
    node.setBoolProperty("useSwitchingFunction", force.getUseSwitchingFunction());
    node.setDoubleProperty("switchingDistance", force.getSwitchingDistance());
    node.setDoubleProperty("reactionFieldDielectric", force.getReactionFieldDielectric());
    SerializationNode& sites = node.createChildNode("Sites");
    for (int i = 0; i < force.getNumSites(); i++) {
        int particle, reference1, reference2;
        StickyDipoleForce::SiteParameters p;
        force.getSiteParameters(i, particle, reference1, reference2, p);
        sites.createChildNode("Site").setIntProperty("particle", particle).setIntProperty("reference1", reference1)
             .setIntProperty("reference2", reference2).setDoubleProperty("sigma", p.sigma).setDoubleProperty("epsilon", p.epsilon)
             .setDoubleProperty("dipole", p.dipole).setDoubleProperty("nu0", p.nu0).setDoubleProperty("rL", p.rL).setDoubleProperty("rU", p.rU)
             .setDoubleProperty("nu0Prime", p.nu0Prime).setDoubleProperty("rLPrime", p.rLPrime).setDoubleProperty("rUPrime", p.rUPrime)
             .setDoubleProperty("w0", p.w0);
    }
    SerializationNode& exclusions = node.createChildNode("Exclusions");
    for (int i = 0; i < force.getNumExclusions(); i++) {
        int site1, site2;
        force.getExclusionSites(i, site1, site2);
        exclusions.createChildNode("Exclusion").setIntProperty("site1", site1).setIntProperty("site2", site2);
    }
}

void* StickyDipoleForceProxy::deserialize(const SerializationNode& node) const {
    // Every property is read without a default, so a file missing one is an error that names it.
    if (node.getIntProperty("version") != Version)
        throw OpenMMException("StickyDipoleForceProxy: unsupported version number "+std::to_string(node.getIntProperty("version"))
                              +" (this plugin reads "+std::to_string(Version)+")");
    std::unique_ptr<StickyDipoleForce> force(new StickyDipoleForce());
    force->setForceGroup(node.getIntProperty("forceGroup"));
    force->setName(node.getStringProperty("name"));
    force->setNonbondedMethod((StickyDipoleForce::NonbondedMethod) node.getIntProperty("method"));
    force->setCutoffDistance(node.getDoubleProperty("cutoff"));
    force->setUseSwitchingFunction(node.getBoolProperty("useSwitchingFunction"));
    force->setSwitchingDistance(node.getDoubleProperty("switchingDistance"));
    force->setReactionFieldDielectric(node.getDoubleProperty("reactionFieldDielectric"));
    for (const SerializationNode& site : node.getChildNode("Sites").getChildren()) {
        StickyDipoleForce::SiteParameters p;
        p.sigma = site.getDoubleProperty("sigma");
        p.epsilon = site.getDoubleProperty("epsilon");
        p.dipole = site.getDoubleProperty("dipole");
        p.nu0 = site.getDoubleProperty("nu0");
        p.rL = site.getDoubleProperty("rL");
        p.rU = site.getDoubleProperty("rU");
        p.nu0Prime = site.getDoubleProperty("nu0Prime");
        p.rLPrime = site.getDoubleProperty("rLPrime");
        p.rUPrime = site.getDoubleProperty("rUPrime");
        p.w0 = site.getDoubleProperty("w0");
        force->addSite(site.getIntProperty("particle"), site.getIntProperty("reference1"), site.getIntProperty("reference2"), p);
    }
    for (const SerializationNode& exclusion : node.getChildNode("Exclusions").getChildren())
        force->addExclusion(exclusion.getIntProperty("site1"), exclusion.getIntProperty("site2"));
    return force.release();
}
