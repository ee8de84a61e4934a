#include "internal/PositivelySplitEwald.h"
#include "internal/PseParameters.h"
#include "internal/PseRealSpace.h"
#include "internal/PseWaveSpace.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

bool finite(const Vec3& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

} // namespace

PositivelySplitEwald::PositivelySplitEwald(double tolerance, double splitting, const KrylovSolvers::ParallelFor& parallel) :
        tolerance(tolerance), splitting(splitting), memoryBudget(DefaultMemoryBudget), memoryBytes(0), parallel(parallel), numBlobs(0),
        parameters(new PseParameters()), real(new PseRealSpace()), wave(new PseWaveSpace()) {
    if (!(tolerance > 0 && tolerance <= MaxTolerance))
        throw OpenMMException("PositivelySplitEwald: the tolerance epsilon ("+PseParameterChoice::format(tolerance)+") is out of range: give one above 0 and at most "+
                PseParameterChoice::format(MaxTolerance));
    if (tolerance < MinTolerance)
        throw OpenMMException("PositivelySplitEwald: the tolerance epsilon "+PseParameterChoice::format(tolerance)+" is below what double precision reaches ("+
                PseParameterChoice::format(MinTolerance)+": the real-space closed forms and the FFTs round at about that): give epsilon at least "+PseParameterChoice::format(MinTolerance)+
                ", or use the dense PeriodicRotnePragerYamakawa");
    if (!(splitting >= 0 && std::isfinite(splitting)))
        throw OpenMMException("PositivelySplitEwald: the splitting xi ("+PseParameterChoice::format(splitting)+" /nm) must be positive and finite, or 0 to choose one");
}

PositivelySplitEwald::~PositivelySplitEwald() {
}

void PositivelySplitEwald::setMemoryBudget(double bytes) {
    if (!(bytes > 0))
        throw OpenMMException("PositivelySplitEwald: the memory budget must be a positive number of bytes");
    memoryBudget = bytes;
}

void PositivelySplitEwald::checkBlobs(const vector<Vec3>& positions, const vector<double>& radii, const Vec3* boxVectors) const {
    if (boxVectors == NULL)
        throw OpenMMException("PositivelySplitEwald: the positively split Ewald sum needs a periodic box (give setBlobs() the box vectors), "
                "or use HostBlobMobility in an unbounded solvent");
    for (int d = 0; d < 3; d++)
        if (!finite(boxVectors[d]))
            throw OpenMMException("PositivelySplitEwald: box vector "+std::to_string(d)+" is not finite");
    if (!(boxVectors[0].dot(boxVectors[1].cross(boxVectors[2])) > 0))
        throw OpenMMException("PositivelySplitEwald: the box vectors span no volume (they must be right-handed and independent)");
    if (positions.empty() || positions.size() != radii.size())
        throw OpenMMException("PositivelySplitEwald: give one radius per blob, and at least one blob ("+std::to_string(positions.size())+
                " positions, "+std::to_string(radii.size())+" radii)");
    for (int i = 0; i < (int) positions.size(); i++) {
        if (!finite(positions[i]))
            throw OpenMMException("PositivelySplitEwald: the position of blob "+std::to_string(i)+" is not finite");
        if (!(radii[i] > 0 && std::isfinite(radii[i])))
            throw OpenMMException("PositivelySplitEwald: the radius of blob "+std::to_string(i)+" ("+PseParameterChoice::format(radii[i])+" nm) must be positive and finite");
    }
}

void PositivelySplitEwald::setBlobs(const vector<Vec3>& positions, const vector<double>& radii, const Vec3* boxVectors) {
    checkBlobs(positions, radii, boxVectors);
    vector<double> distinct(radii);
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    if ((int) distinct.size() > MaxRadii)
        throw PseRefusal(PseRefusal::TooManyRadii, "PositivelySplitEwald: the blobs have "+std::to_string(distinct.size())+" distinct radii; at most "+
                std::to_string(MaxRadii)+" are supported (each costs two FFTs per product): give the blobs at most "+std::to_string(MaxRadii)+
                " radii, or use the dense PeriodicRotnePragerYamakawa");
    vector<int> group(radii.size());
    PseBlobSummary summary = {(int) positions.size(), (int) distinct.size(), distinct.back(), 0.0};
    for (int i = 0; i < summary.numBlobs; i++) {
        group[i] = std::lower_bound(distinct.begin(), distinct.end(), radii[i])-distinct.begin();
        summary.meanRadius += radii[i]/summary.numBlobs;
    }
    numBlobs = 0;  // unusable until both parts are set
    *parameters = PseParameterChoice::choose(tolerance, splitting, boxVectors, summary, memoryBudget);
    const PseParameters& p = *parameters;
    const double budget = memoryBudget;
    real->setBlobs(positions, group, distinct, boxVectors, p, parallel, [&] (double numPairs) {
        PseParameterChoice::checkBudget(p, summary, numPairs, budget);
    });
    wave->setBlobs(positions, group, distinct, boxVectors, p, parallel);
    memoryBytes = PseParameterChoice::gridBytes(p, summary)+real->getNumPairs()*PseParameterChoice::bytesPerPair(p.tolerance);
    numBlobs = summary.numBlobs;
}

void PositivelySplitEwald::checkSize(const Eigen::VectorXd& f) const {
    if (numBlobs == 0)
        throw OpenMMException("PositivelySplitEwald: call setBlobs() before a product");
    if (f.size() != 3*numBlobs)
        throw OpenMMException("PositivelySplitEwald: the forces have "+std::to_string(f.size())+" components for "+std::to_string(numBlobs)+
                " blobs (3 per blob)");
}

void PositivelySplitEwald::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    checkSize(f);
    Eigen::VectorXd waveSpace;
    wave->multiply(f, waveSpace, parallel);
    real->multiply(f, out, parallel);
    out += waveSpace;
}

void PositivelySplitEwald::multiplyRealSpace(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    checkSize(f);
    real->multiply(f, out, parallel);
}

void PositivelySplitEwald::multiplyWaveSpace(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    checkSize(f);
    wave->multiply(f, out, parallel);
}

KrylovSolvers::Result PositivelySplitEwald::sampleRealSpaceNoise(const std::function<double()>& normal, Eigen::VectorXd& out,
                                                                 double lanczosTolerance, int maxLanczosIterations) {
    if (numBlobs == 0)
        throw OpenMMException("PositivelySplitEwald: call setBlobs() before sampling noise");
    Eigen::VectorXd w(3*numBlobs);
    for (int i = 0; i < 3*numBlobs; i++)
        w[i] = normal();
    KrylovSolvers::Operator realSpace = [&] (const Eigen::VectorXd& in, Eigen::VectorXd& result) {
        real->multiply(in, result, parallel);
    };
    return KrylovSolvers::lanczosSquareRoot(realSpace, w, out, lanczosTolerance, maxLanczosIterations);
}

void PositivelySplitEwald::sampleWaveSpaceNoise(const std::function<double()>& normal, Eigen::VectorXd& out) {
    if (numBlobs == 0)
        throw OpenMMException("PositivelySplitEwald: call setBlobs() before sampling noise");
    wave->sampleNoise(normal, out, parallel);
}

KrylovSolvers::Result PositivelySplitEwald::sampleNoise(const std::function<double()>& normal, Eigen::VectorXd& out, double lanczosTolerance,
                                                        int maxLanczosIterations) {
    const KrylovSolvers::Result result = sampleRealSpaceNoise(normal, out, lanczosTolerance, maxLanczosIterations);
    Eigen::VectorXd waveSpace;
    sampleWaveSpaceNoise(normal, waveSpace);
    out += waveSpace;
    return result;
}

long long PositivelySplitEwald::getNumNoiseNormals() const {
    return 3LL*numBlobs+(numBlobs > 0 ? wave->getNumNormals() : 0);
}

double PositivelySplitEwald::getSplitting() const {
    return (numBlobs > 0 ? parameters->xi : splitting);
}

double PositivelySplitEwald::getRealSpaceCutoff() const {
    return parameters->realCutoff;
}

void PositivelySplitEwald::getGridSize(int size[3]) const {
    for (int d = 0; d < 3; d++)
        size[d] = parameters->grid[d];
}

int PositivelySplitEwald::getSupport() const {
    return parameters->support;
}

long long PositivelySplitEwald::getNumPairs() const {
    return real->getNumPairs();
}

double PositivelySplitEwald::getMemoryBytes() const {
    return memoryBytes;
}

const PseParameters& PositivelySplitEwald::getParameters() const {
    if (numBlobs == 0)
        throw OpenMMException("PositivelySplitEwald: getParameters() before setBlobs() with blobs");
    return *parameters;
}

const PseRealSpace& PositivelySplitEwald::getRealSpace() const {
    return *real;
}

const PseWaveSpace& PositivelySplitEwald::getWaveSpace() const {
    return *wave;
}
