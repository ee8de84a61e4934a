#include "internal/RotnePragerBlake.h"
#include "internal/BeadHydrodynamics.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/MessageFormat.h"
#include "internal/RotnePragerYamakawa.h"

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::MessageFormat;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

/** A blob as the regularised mobility sees it: raised to its evaluated height h~, with its damping. */
struct RaisedBlob {
    double x, y, height, radius, damping;
};

vector<RaisedBlob> raise(const vector<Vec3>& positions, const vector<double>& radii, double wallZ) {
    vector<RaisedBlob> blobs(positions.size());
    for (int i = 0; i < (int) positions.size(); i++) {
        const double h = positions[i][2]-wallZ;
        blobs[i] = {positions[i][0], positions[i][1], RotnePragerBlake::evaluatedHeight(h, radii[i]), radii[i], RotnePragerBlake::damping(h, radii[i])};
    }
    return blobs;
}

/** mu_ij of two distinct raised blobs, undamped: the free part plus the image part. */
void pairBlock(const RaisedBlob& i, const RaisedBlob& j, double block[9]) {
    double image[9];
    RotnePragerYamakawa::mobilityBlock(j.x-i.x, j.y-i.y, j.height-i.height, i.radius, j.radius, block);
    RotnePragerBlake::imageBlock(i.x-j.x, i.y-j.y, i.height, j.height, i.radius, j.radius, image);
    for (int k = 0; k < 9; k++)
        block[k] += image[k];
}

/** v += mu_ij f for two distinct raised blobs, undamped, without forming the block (the product's inner loop). */
inline void addPairProduct(const RaisedBlob& i, const RaisedBlob& j, const double* f, double v[3]) {
    const double dx = i.x-j.x, dy = i.y-j.y, dz = i.height-j.height;
    double isotropic, dyadicPerR2;
    RotnePragerYamakawa::pairCoefficients(dx*dx+dy*dy+dz*dz, i.radius, j.radius, isotropic, dyadicPerR2);
    const double free = dyadicPerR2*(dx*f[0]+dy*f[1]+dz*f[2]);
    double c[5];
    RotnePragerBlake::imageCoefficients(dx, dy, i.height, j.height, i.radius, j.radius, c);
    const double rz = i.height+j.height;
    const double dyadic = c[1]*(dx*f[0]+dy*f[1]+rz*f[2])+c[2]*f[2];
    v[0] += (isotropic+c[0])*f[0]+free*dx+dyadic*dx;
    v[1] += (isotropic+c[0])*f[1]+free*dy+dyadic*dy;
    v[2] += (isotropic+c[0])*f[2]+free*dz+dyadic*rz+c[3]*(dx*f[0]+dy*f[1]+rz*f[2])+c[4]*f[2];
}

} // namespace

void RotnePragerBlake::validate(const std::string& caller, const vector<Vec3>& positions, const vector<double>& radii, double wallZ,
                                const std::function<std::string (int)>& names) {
    auto name = [&] (int i) { return names ? names(i) : "blob "+std::to_string(i); };
    if (!std::isfinite(wallZ))
        throw OpenMMException(caller+": the wall's height is "+str(wallZ)+"; give a finite z (nm)");
    vector<Vec3> raised(positions);
    vector<double> keys(positions.size());
    for (int i = 0; i < (int) positions.size(); i++) {
        const double h = positions[i][2]-wallZ;
        if (!(h > 0) || !std::isfinite(h))
            throw BlobBelowWallException(caller+": "+name(i)+" has its centre at z = "+str(positions[i][2])+" nm, at or below the no-slip wall at z = "+
                                         str(wallZ)+" nm; the fluid is above the wall, so every blob's centre must be too: place its body above the wall", i);
        raised[i][2] = wallZ+evaluatedHeight(h, radii[i]);
        keys[i] = positions[i][0];
    }
    if (positions.empty())
        return;
    std::pair<int, int> same = BeadHydrodynamics::findCoincident(keys, 0, [&] (int i, int j) { return raised[i]-raised[j]; }, radii);
    if (same.first >= 0)
        throw OpenMMException(caller+": "+name(same.first)+" and "+name(same.second)+" have the same radius and lie one above the other within a radius "
                              "of the wall; its mobility is evaluated with such blobs raised to one radius above the wall, where these two become the "
                              "same sphere and the mobility singular: move them apart or keep one of them");
}

Eigen::MatrixXd RotnePragerBlake::mobilityMatrix(const vector<Vec3>& positions, const vector<double>& radii, double wallZ,
                                                 const KrylovSolvers::ParallelFor& parallel) {
    const vector<RaisedBlob> blobs = raise(positions, radii, wallZ);
    return CoupledResistanceMath::lowerTriangle(blobs.size(), [&] (int i, int j, double block[9]) {
        if (i == j) {
            double parallelToWall, perpendicular;
            selfMobility(blobs[i].height, blobs[i].radius, parallelToWall, perpendicular);
            for (int k = 0; k < 9; k++)
                block[k] = 0;
            block[0] = block[4] = parallelToWall;
            block[8] = perpendicular;
        }
        else
            pairBlock(blobs[i], blobs[j], block);
        const double damping = blobs[i].damping*blobs[j].damping;
        for (int k = 0; k < 9; k++)
            block[k] *= damping;
    }, parallel);
}

void RotnePragerBlake::mobilityProduct(const vector<Vec3>& positions, const vector<double>& radii, double wallZ, const Eigen::VectorXd& f,
                                       Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel) {
    const vector<RaisedBlob> blobs = raise(positions, radii, wallZ);
    const int n = blobs.size();
    // M~ f = B M(h~) (B f).
    Eigen::VectorXd damped(3*n);
    for (int j = 0; j < n; j++)
        damped.segment<3>(3*j) = blobs[j].damping*f.segment<3>(3*j);
    out.resize(3*n);
    parallel(n, [&] (int begin, int end) {
        for (int i = begin; i < end; i++) {
            double parallelToWall, perpendicular;
            selfMobility(blobs[i].height, blobs[i].radius, parallelToWall, perpendicular);
            double v[3] = {parallelToWall*damped[3*i], parallelToWall*damped[3*i+1], perpendicular*damped[3*i+2]};
            for (int j = 0; j < n; j++)
                if (j != i)
                    addPairProduct(blobs[i], blobs[j], &damped[3*j], v);
            for (int k = 0; k < 3; k++)
                out[3*i+k] = blobs[i].damping*v[k];
        }
    });
}
