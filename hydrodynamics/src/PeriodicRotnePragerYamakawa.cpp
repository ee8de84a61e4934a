#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/BeadHydrodynamics.h"
#include "internal/HasimotoSplit.h"
#include "internal/MessageFormat.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <limits>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::MessageFormat;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

/** Terms below this fraction of the leading ones are left out of both sums. */
const double Tolerance = 1e-16;
/** Hasimoto's weight phi(k) = (1 + x) exp(-x), x = k^2/4xi^2, is below Tolerance beyond x = this. */
const double WaveCutoffX = 41.5;
/** F(r) falls as exp(-(xi (r - a_i - a_j))^2): beyond contact by this over xi it is below Tolerance. */
const double RealCutoff = 6.5;

double sinc(double x) {
    return (std::abs(x) < 1e-4 ? 1-x*x/6 : std::sin(x)/x);
}

/** The pair (i, j), i <= j, of index p in the row-by-row list of an n x n upper triangle. */
void trianglePair(long long p, int n, int& i, int& j) {
    // Row i starts at i n - i (i - 1)/2; invert that quadratic, then correct its rounding.
    const double b = 2.0*n+1;
    i = (int) ((b-std::sqrt(b*b-8.0*p))/2);
    auto rowStart = [n] (long long row) { return row*n-row*(row-1)/2; };
    while (i > 0 && rowStart(i) > p)
        i--;
    while (i+1 < n && rowStart(i+1) <= p)
        i++;
    j = i+(int) (p-rowStart(i));
}

} // namespace

PeriodicRotnePragerYamakawa::PeriodicRotnePragerYamakawa(const Vec3 boxVectors[3], double splitting) {
    for (int i = 0; i < 3; i++) {
        box[i] = boxVectors[i];
        if (!std::isfinite(box[i][0]) || !std::isfinite(box[i][1]) || !std::isfinite(box[i][2]))
            throw OpenMMException("PeriodicRotnePragerYamakawa: box vector "+std::to_string(i)+" is not finite");
    }
    volume = box[0].dot(box[1].cross(box[2]));
    if (!(volume > 0))
        throw OpenMMException("PeriodicRotnePragerYamakawa: the box vectors span no volume (they must be right-handed and independent)");
    for (int i = 0; i < 3; i++)
        reciprocal[i] = box[(i+1)%3].cross(box[(i+2)%3])*(2*M_PI/volume);
    // xi = 5/L: about a dozen images of each pair in real space and a few thousand wave vectors,
    // where the wave-space sum runs as matrix products and so costs less per term.
    xi = (splitting > 0 ? splitting : 5/std::cbrt(volume));
    if (!std::isfinite(xi))
        throw OpenMMException("PeriodicRotnePragerYamakawa: the splitting parameter is not finite");
    realCutoffBeyondContact = RealCutoff/xi;
    waveCutoff = 2*xi*std::sqrt(WaveCutoffX);
}

Vec3 PeriodicRotnePragerYamakawa::reduced(Vec3 d) const {
    d -= box[2]*std::round(d.dot(reciprocal[2])/(2*M_PI));
    d -= box[1]*std::round(d.dot(reciprocal[1])/(2*M_PI));
    d -= box[0]*std::round(d.dot(reciprocal[0])/(2*M_PI));
    return d;
}

double PeriodicRotnePragerYamakawa::getSmallestWidth() const {
    double width = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; i++)
        width = std::min(width, 2*M_PI/std::sqrt(reciprocal[i].dot(reciprocal[i])));
    return width;
}

void PeriodicRotnePragerYamakawa::validate(const std::string& caller, const vector<Vec3>& positions, const vector<double>& radii,
                                           const std::function<std::string (int)>& names) const {
    const double halfWidth = 0.5*getSmallestWidth();
    for (int i = 0; i < (int) radii.size(); i++)
        if (!(2*radii[i] < halfWidth))
            throw OpenMMException(caller+": "+names(i)+" has radius "+str(radii[i])+" nm, too large for the periodic box: a blob's diameter must be under "
                    "half the box's smallest width ("+str(halfWidth)+" nm), so that blobs overlap no more than the nearest image of each other (as a "
                    "body must be narrower than half the box). Use a larger box, or smaller blobs (radius under "+str(0.5*halfWidth)+" nm)");
    // The same sphere through the box: sorted by the distance from the planes of box vectors 1
    // and 2, wrapped into the box.
    const double spacing = 2*M_PI/std::sqrt(reciprocal[0].dot(reciprocal[0]));
    vector<double> keys(positions.size());
    for (int i = 0; i < (int) positions.size(); i++) {
        double s = positions[i].dot(reciprocal[0])/(2*M_PI);
        keys[i] = (s-std::floor(s))*spacing;
    }
    std::pair<int, int> same = BeadHydrodynamics::findCoincident(keys, spacing, [&](int i, int j) { return reduced(positions[j]-positions[i]); }, radii);
    if (same.first >= 0) {
        int i = same.first, j = same.second;
        throw OpenMMException(caller+": "+names(i)+" and "+names(j)+" are the same sphere through the periodic box: they are a box vector apart ("+
                describe(positions[i])+" and "+describe(positions[j])+" nm), with radius "+str(radii[i])+" nm, so their mobility would be singular. "
                "Remove one of them (positions on both faces of the box, such as 0 and the box's side, are the same place)");
    }
}

void PeriodicRotnePragerYamakawa::realSpaceBlock(const Vec3& d, double ai, double aj, double block[9]) const {
    HasimotoSplit::realSpaceBlock(d, ai, aj, xi, block);
}

Eigen::MatrixXd PeriodicRotnePragerYamakawa::mobility(const vector<Vec3>& positions, const vector<double>& radii, const ParallelFor& parallel) const {
    const int n = positions.size();
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3*n, 3*n);
    addRealSpace(positions, radii, m, parallel);
    addWaveSpace(positions, radii, m, parallel);
    return m;
}

void PeriodicRotnePragerYamakawa::addRealSpace(const vector<Vec3>& positions, const vector<double>& radii, Eigen::MatrixXd& m, const ParallelFor& parallel) const {
    // Every image of every pair (a blob's own images included) within the cutoff.
    const int n = positions.size();
    double maxRadius = 0;
    for (double a : radii)
        maxRadius = std::max(maxRadius, a);
    const double cutoff = 2*maxRadius+realCutoffBeyondContact;
    int range[3];
    for (int i = 0; i < 3; i++) {
        double planeSpacing = 2*M_PI/std::sqrt(reciprocal[i].dot(reciprocal[i]));
        range[i] = (int) std::ceil(cutoff/planeSpacing)+1;
    }
    // The pairs i <= j shared out evenly; each writes its own two blocks.
    const long long numPairs = (long long) n*(n+1)/2;
    const int numChunks = (int) std::min<long long>(numPairs, 1024);
    parallel(numChunks, [&] (int firstChunk, int endChunk) {
        for (long long p = numPairs*firstChunk/numChunks; p < numPairs*endChunk/numChunks; p++) {
            int i, j;
            trianglePair(p, n, i, j);
            // Into the box's reduced cell first, so that the image ranges cover the cutoff.
            Vec3 d = reduced(positions[j]-positions[i]);
            const double pairCutoff = radii[i]+radii[j]+realCutoffBeyondContact;
            double sum[9] = {0};
            for (int u = -range[0]; u <= range[0]; u++)
                for (int v = -range[1]; v <= range[1]; v++)
                    for (int w = -range[2]; w <= range[2]; w++) {
                        Vec3 image = d+box[0]*u+box[1]*v+box[2]*w;
                        if (image.dot(image) >= pairCutoff*pairCutoff)
                            continue;
                        double block[9];
                        realSpaceBlock(image, radii[i], radii[j], block);
                        for (int k = 0; k < 9; k++)
                            sum[k] += block[k];
                    }
            for (int k = 0; k < 3; k++)
                for (int l = 0; l < 3; l++) {
                    m(3*i+k, 3*j+l) = sum[3*k+l];
                    m(3*j+l, 3*i+k) = sum[3*k+l];
                }
        }
    });
}

vector<Vec3> PeriodicRotnePragerYamakawa::waveVectors() const {
    // Half the lattice: k and -k give the same term.
    int waveRange[3];
    for (int i = 0; i < 3; i++)
        waveRange[i] = (int) std::ceil(waveCutoff*std::sqrt(box[i].dot(box[i]))/(2*M_PI));
    vector<Vec3> waves;
    for (int u = 0; u <= waveRange[0]; u++)
        for (int v = (u == 0 ? 0 : -waveRange[1]); v <= waveRange[1]; v++)
            for (int w = (u == 0 && v == 0 ? 1 : -waveRange[2]); w <= waveRange[2]; w++) {
                Vec3 k = reciprocal[0]*u+reciprocal[1]*v+reciprocal[2]*w;
                if (k.dot(k) <= waveCutoff*waveCutoff)
                    waves.push_back(k);
            }
    return waves;
}

void PeriodicRotnePragerYamakawa::addWaveSpace(const vector<Vec3>& positions, const vector<double>& radii, Eigen::MatrixXd& m, const ParallelFor& parallel) const {
    // With c_i = sinc(k a_i) cos(k.r_i) and s_i likewise with sin, component (x, y) of the pair
    // blocks gains w (I - kk)_xy (c c^T + s s^T), summed over all k as matrix products.
    const int n = positions.size();
    const vector<Vec3> waves = waveVectors();
    const int numWaves = waves.size();
    Eigen::MatrixXd c(n, numWaves), s(n, numWaves), weights(6, numWaves);
    const int component[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    parallel(numWaves, [&] (int begin, int end) {
        for (int q = begin; q < end; q++) {
            const Vec3& k = waves[q];
            double k2 = k.dot(k), kk = std::sqrt(k2);
            double w = 2*HasimotoSplit::weight(k2, xi)/(k2*volume);
            for (int p = 0; p < 6; p++) {
                int x = component[p][0], y = component[p][1];
                weights(p, q) = w*((x == y ? 1.0 : 0.0)-k[x]*k[y]/k2);
            }
            for (int i = 0; i < n; i++) {
                double phase = k.dot(positions[i]), size = sinc(kk*radii[i]);
                c(i, q) = size*std::cos(phase);
                s(i, q) = size*std::sin(phase);
            }
        }
    });
    // Row blocks of each product on their own thread; each writes its own rows of m.
    const int rowBlock = 32, numRowBlocks = (n+rowBlock-1)/rowBlock;
    parallel(6*numRowBlocks, [&] (int begin, int end) {
        for (int task = begin; task < end; task++) {
            const int p = task/numRowBlocks, first = (task%numRowBlocks)*rowBlock, rows = std::min(rowBlock, n-first);
            const int x = component[p][0], y = component[p][1];
            Eigen::MatrixXd sum = c.middleRows(first, rows)*weights.row(p).asDiagonal()*c.transpose()+
                                  s.middleRows(first, rows)*weights.row(p).asDiagonal()*s.transpose();
            for (int i = first; i < first+rows; i++)
                for (int j = 0; j < n; j++) {
                    m(3*i+x, 3*j+y) += sum(i-first, j);
                    if (x != y)
                        m(3*i+y, 3*j+x) += sum(i-first, j);
                }
        }
    });
}
