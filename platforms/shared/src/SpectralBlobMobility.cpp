#include "internal/SpectralBlobMobility.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <sstream>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;

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
        throw OpenMMException(integratorName+": the spectral solver (setHydrodynamicSolver()) cannot take these blobs. "+e.what()+
                ". From the integrator: raise setHydrodynamicMemoryBudget() (the budget), loosen setHydrodynamicTolerance() (epsilon: a coarser grid "
                "and fewer real-space pairs), use fewer blobs or a bigger box, or another solver (DenseSolver or KrylovSolver: the dense Ewald "
                "sum, O(B^2) memory)");
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
