#include "internal/SpectralBlobMobility.h"
#include "internal/PseParameters.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <sstream>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;

namespace {

/** What a user of the integrator changes for each of the PSE's refusals. */
std::string remedy(PseRefusal::Reason reason) {
    switch (reason) {
    case PseRefusal::MemoryBudget:
        // The dense Ewald sum would need far more (72 B^2 bytes), so no other solver is offered.
        return "raise setHydrodynamicMemoryBudget() (the budget), loosen setHydrodynamicTolerance() (epsilon: a coarser grid and fewer "
               "real-space pairs), or use fewer blobs";
    case PseRefusal::TooManyRadii:
        return "give the blobs at most "+std::to_string(PositivelySplitEwald::MaxRadii)+" distinct radii (setParticleRadius(), setBodyBlobs()), "
               "or setHydrodynamicSolver(KrylovSolver) for the dense Ewald sum (any radii, O(B^2) memory and time)";
    case PseRefusal::BoxTooSmall:
    default:
        return "use a bigger box (every solver needs its narrowest width above 4 blob radii)";
    }
}

} // namespace

SpectralBlobMobility::SpectralBlobMobility(const std::string& integratorName, const KrylovSolvers::ParallelFor& parallel) :
        integratorName(integratorName), parallel(parallel), memoryBudget(PositivelySplitEwald::DefaultMemoryBudget) {
}

void SpectralBlobMobility::setMemoryBudget(double bytes) {
    memoryBudget = bytes;
    if (product)
        product->setMemoryBudget(bytes);
}

void SpectralBlobMobility::setTolerance(double tolerance) {
    if (product && product->getTolerance() == tolerance)
        return;
    if (tolerance < PositivelySplitEwald::MinTolerance) {
        std::ostringstream message;
        message << integratorName << ": the spectral solver's periodic mobility (positively split Ewald) takes its tolerance epsilon from "
                "setHydrodynamicTolerance(), here " << tolerance << ", below the " << PositivelySplitEwald::MinTolerance << " it can reach in double "
                "precision: call setHydrodynamicTolerance() with at least " << PositivelySplitEwald::MinTolerance << ", or "
                "setHydrodynamicSolver(KrylovSolver) for the dense Ewald sum (O(B^2) memory and time)";
        throw OpenMMException(message.str());
    }
    product.reset(new PositivelySplitEwald(std::min(tolerance, PositivelySplitEwald::MaxTolerance), 0, parallel));
    product->setMemoryBudget(memoryBudget);
}

void SpectralBlobMobility::setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors) {
    if (!product)
        throw OpenMMException("SpectralBlobMobility: call setTolerance() before setBlobs()");
    try {
        product->setBlobs(positions, radii, boxVectors);
    }
    catch (const OpenMMException& e) {
        // A refusal that other settings would lift names the integrator's; unusable input needs no more than its own message.
        const PseRefusal* refusal = dynamic_cast<const PseRefusal*>(&e);
        throw OpenMMException(integratorName+": the spectral solver (setHydrodynamicSolver()) cannot take these blobs. "+e.what()+
                (refusal ? ". From the integrator: "+remedy(refusal->getReason()) : ""));
    }
}


void SpectralBlobMobility::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    product->multiply(f, out);
}

KrylovSolvers::Result SpectralBlobMobility::sampleNoise(const std::function<double()>& normal, Eigen::VectorXd& out, double tolerance,
                                                        int maxIterations) {
    return product->sampleNoise(normal, out, tolerance, maxIterations);
}

const PositivelySplitEwald& SpectralBlobMobility::getProduct() const {
    if (!product)
        throw OpenMMException("SpectralBlobMobility: call setTolerance() first");
    return *product;
}
