#include "internal/ShellModel.h"
#include "internal/BeadHydrodynamics.h"
#include "openmm/OpenMMException.h"
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::ResistanceMath;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::string;
using std::vector;

namespace {

/**
 * Distance between neighbouring bead centres, in bead radii: a gap of one bead radius between
 * beads. Touching beads (2) are the classical choice, but the shell's error then has a larger
 * quadratic part: measured on a sphere and on spheroids of axial ratio 2 and 5 at 500-2000 beads,
 * the linear extrapolation is two to three times closer to Stokes and Perrin at 3 than at 2 for
 * the same number of beads (for rotation at 1000 beads: within 0.7% instead of 2.3%), and it
 * converges to the same limit.
 */
const double BEAD_SPACING = 3.0;

/**
 * More beads than any bead model can be solved with (72 N^2 bytes: 7 TB at 1e7 beads); a tiling
 * that would exceed it comes from a bead radius far too small for the surface.
 */
const double MAX_TILING_BEADS = 1e7;

/** Points of the meridian arc-length table: far finer than any tiling needs. */
const int ARC_TABLE_SIZE = 4096;

/**
 * Beads already placed, binned in cubes so that the beads closer than the cube's side to a point
 * are all in the 27 cubes around it.
 */
class BeadGrid {
public:
    explicit BeadGrid(double cellSize) : cellSize(cellSize) {
    }
    bool hasBeadWithin(const Vec3& p, double distance) const {
        int64_t c[3];
        cell(p, c);
        for (int64_t i = c[0]-1; i <= c[0]+1; i++)
            for (int64_t j = c[1]-1; j <= c[1]+1; j++)
                for (int64_t k = c[2]-1; k <= c[2]+1; k++) {
                    auto found = beads.find(key(i, j, k));
                    if (found == beads.end())
                        continue;
                    for (const Vec3& q : found->second) {
                        Vec3 d = p-q;
                        if (d.dot(d) < distance*distance)
                            return true;
                    }
                }
        return false;
    }
    void add(const Vec3& p) {
        int64_t c[3];
        cell(p, c);
        beads[key(c[0], c[1], c[2])].push_back(p);
    }
private:
    void cell(const Vec3& p, int64_t* c) const {
        for (int k = 0; k < 3; k++)
            c[k] = (int64_t) std::floor(p[k]/cellSize);
    }
    static uint64_t key(int64_t i, int64_t j, int64_t k) {
        const int64_t offset = int64_t(1) << 20;
        return ((uint64_t) (i+offset) << 42) ^ ((uint64_t) (j+offset) << 21) ^ (uint64_t) (k+offset);
    }
    double cellSize;
    std::unordered_map<uint64_t, vector<Vec3> > beads;
};

void checkBeadRadius(const string& caller, double beadRadius) {
    if (!(beadRadius > 0) || !std::isfinite(beadRadius))
        throw OpenMMException(caller+": the shell's bead radius is "+std::to_string(beadRadius)+"; it must be positive and finite (nm)");
}

} // namespace

vector<Vec3> ShellModel::tileSpheroid(double a, double b, double beadRadius) {
    checkBeadRadius("ShellModel::tileSpheroid", beadRadius);
    if (!(a > 0) || !(b > 0) || !std::isfinite(a) || !std::isfinite(b))
        throw OpenMMException("ShellModel::tileSpheroid: the semi-axes are "+std::to_string(a)+" and "+std::to_string(b)+"; they must be positive and finite (nm)");
    // The meridian (a cos t, b sin t), t in [0, pi], tabulated by arc length (Simpson's rule per
    // interval) so that rings can be spaced evenly along it.
    vector<double> arc(ARC_TABLE_SIZE+1, 0.0);
    auto speed = [&](double t) { return std::sqrt(a*a*std::sin(t)*std::sin(t)+b*b*std::cos(t)*std::cos(t)); };
    const double dt = M_PI/ARC_TABLE_SIZE;
    for (int i = 0; i < ARC_TABLE_SIZE; i++) {
        double t = i*dt;
        arc[i+1] = arc[i]+dt/6*(speed(t)+4*speed(t+dt/2)+speed(t+dt));
    }
    const double length = arc.back();
    // The surface area is below the meridian's length times the circumference 2 pi b.
    double estimate = length*2*M_PI*b/((BEAD_SPACING*beadRadius)*(BEAD_SPACING*beadRadius));
    if (estimate > MAX_TILING_BEADS)
        throw OpenMMException("ShellModel::tileSpheroid: a bead radius of "+std::to_string(beadRadius)+" nm would cover a surface of semi-axes "+std::to_string(a)+
                " and "+std::to_string(b)+" nm with about "+std::to_string(estimate)+" beads, far more than can be solved; use a larger bead radius");
    const int numRings = std::max(1L, std::lround(length/(BEAD_SPACING*beadRadius)));
    vector<Vec3> beads;
    int interval = 0;
    for (int ring = 0; ring < numRings; ring++) {
        double s = (ring+0.5)*length/numRings;
        while (interval+1 < ARC_TABLE_SIZE && arc[interval+1] < s)
            interval++;
        double t = (interval+(s-arc[interval])/(arc[interval+1]-arc[interval]))*dt;
        double x = a*std::cos(t), rho = b*std::sin(t);
        const int numBeads = std::max(1L, std::lround(2*M_PI*rho/(BEAD_SPACING*beadRadius)));
        // Alternate rings are turned by half a spacing, so that beads of neighbouring rings do not
        // line up along meridians.
        double phase = (ring%2 == 0 ? 0.0 : 0.5);
        for (int j = 0; j < numBeads; j++) {
            double phi = 2*M_PI*(j+phase)/numBeads;
            beads.push_back(Vec3(x, rho*std::cos(phi), rho*std::sin(phi)));
        }
    }
    return beads;
}

void ShellModel::validateSpheres(const string& caller, const vector<Vec3>& centers, const vector<double>& radii) {
    if (centers.empty())
        throw OpenMMException(caller+": there are no spheres (atoms) to cover; give at least one");
    if (centers.size() != radii.size())
        throw OpenMMException(caller+": got "+std::to_string(centers.size())+" sphere centres but "+std::to_string(radii.size())+" radii; give one radius per sphere");
    for (int i = 0; i < (int) centers.size(); i++) {
        if (!std::isfinite(centers[i][0]) || !std::isfinite(centers[i][1]) || !std::isfinite(centers[i][2]))
            throw OpenMMException(caller+": sphere (atom) "+std::to_string(i)+" has a coordinate that is not a finite number");
        if (!(radii[i] > 0) || !std::isfinite(radii[i]))
            throw OpenMMException(caller+": sphere (atom) "+std::to_string(i)+" has radius "+std::to_string(radii[i])+"; radii must be positive and finite (nm)");
    }
}

void ShellModel::validateSpheroids(const string& caller, const vector<Vec3>& centers, const vector<Vec3>& axes, const vector<double>& a,
                                   const vector<double>& b) {
    if (centers.empty())
        throw OpenMMException(caller+": there are no spheroids to cover; give at least one");
    if (axes.size() != centers.size() || a.size() != centers.size() || b.size() != centers.size())
        throw OpenMMException(caller+": got "+std::to_string(centers.size())+" centres, "+std::to_string(axes.size())+" axes, "+std::to_string(a.size())+
                " and "+std::to_string(b.size())+" semi-axes; give one axis and two semi-axes per spheroid");
    for (int i = 0; i < (int) centers.size(); i++) {
        if (!std::isfinite(centers[i][0]) || !std::isfinite(centers[i][1]) || !std::isfinite(centers[i][2]))
            throw OpenMMException(caller+": spheroid "+std::to_string(i)+" has a centre coordinate that is not a finite number");
        double length = std::sqrt(axes[i].dot(axes[i]));
        if (!(length > 0) || !std::isfinite(length))
            throw OpenMMException(caller+": spheroid "+std::to_string(i)+" has an axis of length "+std::to_string(length)+"; give a finite nonzero vector");
        if (!(a[i] > 0) || !(b[i] > 0) || !std::isfinite(a[i]) || !std::isfinite(b[i]))
            throw OpenMMException(caller+": spheroid "+std::to_string(i)+" has semi-axes "+std::to_string(a[i])+" and "+std::to_string(b[i])+
                    "; they must be positive and finite (nm)");
    }
}

Eigen::Matrix3d ShellModel::spheroidFrame(const Vec3& axis) {
    Eigen::Vector3d u = toEigen(axis).normalized();
    // The lab axis least parallel to u, ties to the first: for u along x that is y, and the frame is the lab's.
    int least = 0;
    for (int k = 1; k < 3; k++)
        if (std::abs(u[k]) < std::abs(u[least]))
            least = k;
    Eigen::Vector3d v = Eigen::Vector3d::Unit(least);
    v = (v-v.dot(u)*u).normalized();
    Eigen::Matrix3d frame;
    frame.col(0) = u;
    frame.col(1) = v;
    frame.col(2) = u.cross(v);
    return frame;
}

vector<Vec3> ShellModel::tileSpheroidUnion(const string& caller, const vector<Vec3>& centers, const vector<Vec3>& axes, const vector<double>& a,
                                           const vector<double>& b, double beadRadius) {
    checkBeadRadius(caller, beadRadius);
    validateSpheroids(caller, centers, axes, a, b);
    const int numSpheroids = centers.size();
    vector<Eigen::Matrix3d> frames(numSpheroids);
    for (int i = 0; i < numSpheroids; i++)
        frames[i] = spheroidFrame(axes[i]);
    // Only spheroids whose bounding spheres intersect that of spheroid i can bury its beads.
    vector<vector<int> > neighbors(numSpheroids);
    for (int i = 0; i < numSpheroids; i++)
        for (int j = i+1; j < numSpheroids; j++) {
            Vec3 d = centers[i]-centers[j];
            if (std::sqrt(d.dot(d)) < std::max(a[i], b[i])+std::max(a[j], b[j])) {
                neighbors[i].push_back(j);
                neighbors[j].push_back(i);
            }
        }
    auto inside = [&](int j, const Eigen::Vector3d& p) {
        Eigen::Vector3d local = frames[j].transpose()*(p-toEigen(centers[j]));
        double x = local[0]/a[j], y = local[1]/b[j], z = local[2]/b[j];
        return x*x+y*y+z*z < 1-1e-9;
    };
    vector<Vec3> beads;
    BeadGrid grid(0.5*BEAD_SPACING*beadRadius);
    for (int i = 0; i < numSpheroids; i++) {
        for (const Vec3& offset : tileSpheroid(a[i], b[i], beadRadius)) {
            Eigen::Vector3d q = toEigen(centers[i])+frames[i]*toEigen(offset);
            Vec3 p(q[0], q[1], q[2]);
            bool buried = false;
            for (int j : neighbors[i])
                if (inside(j, q)) {
                    buried = true;
                    break;
                }
            if (buried || grid.hasBeadWithin(p, 0.5*BEAD_SPACING*beadRadius))
                continue;
            grid.add(p);
            beads.push_back(p);
        }
    }
    if (beads.empty())
        throw OpenMMException(caller+": no bead is left on the surface; use a smaller bead radius");
    return beads;
}

vector<Vec3> ShellModel::tileSphereUnion(const vector<Vec3>& centers, const vector<double>& radii, double beadRadius) {
    const string caller = "ShellModel::tileSphereUnion";
    validateSpheres(caller, centers, radii);
    return tileSpheroidUnion(caller, centers, vector<Vec3>(centers.size(), Vec3(1, 0, 0)), radii, radii, beadRadius);
}

Matrix6 ShellModel::extrapolateToZeroBeadSize(const vector<double>& beadRadii, const vector<Matrix6>& tensors) {
    if (beadRadii.size() != tensors.size())
        throw OpenMMException("ShellModel::extrapolateToZeroBeadSize: got "+std::to_string(beadRadii.size())+" bead radii but "+std::to_string(tensors.size())+" tensors");
    const int n = beadRadii.size();
    double mean = 0;
    for (double s : beadRadii)
        mean += s/n;
    double spread = 0;
    for (double s : beadRadii)
        spread += (s-mean)*(s-mean);
    if (n < 2 || !(spread > 0))
        throw OpenMMException("ShellModel::extrapolateToZeroBeadSize: a straight-line extrapolation needs at least two different bead radii");
    // Least squares y = y0 + slope*sigma for every element at once; return y0 = mean(y) - slope*mean(sigma).
    Matrix6 meanTensor = Matrix6::Zero(), covariance = Matrix6::Zero();
    for (int k = 0; k < n; k++)
        meanTensor += tensors[k]/n;
    for (int k = 0; k < n; k++)
        covariance += (beadRadii[k]-mean)*(tensors[k]-meanTensor);
    return meanTensor-(mean/spread)*covariance;
}

vector<double> ShellModel::beadRadii(const Tiling& tiling, double approximateArea, int maxBeads, int numResolutions) {
    if (maxBeads < 20)
        throw OpenMMException("ShellModel::beadRadii: maxBeads is "+std::to_string(maxBeads)+"; a shell needs at least 20 beads at its finest");
    if (numResolutions < 2)
        throw OpenMMException("ShellModel::beadRadii: numResolutions is "+std::to_string(numResolutions)+"; an extrapolation needs at least 2");
    if (!(approximateArea > 0) || !std::isfinite(approximateArea))
        throw OpenMMException("ShellModel::beadRadii: the approximate surface area must be positive and finite");
    // Beads s sigma apart cover about (s sigma)^2 each: N ~ area/(s sigma)^2. Refine that guess
    // with the tiling's own count, which scales as 1/sigma^2.
    double sigma = std::sqrt(approximateArea/maxBeads)/BEAD_SPACING;
    for (int iteration = 0; iteration < 4; iteration++) {
        double count = tiling(sigma).size();
        if (std::abs(count-maxBeads) <= 0.02*maxBeads)
            break;
        sigma *= std::sqrt(count/maxBeads);
    }
    vector<double> radii(numResolutions);
    for (int k = 0; k < numResolutions; k++)
        radii[k] = sigma*(1+k/(numResolutions-1.0));
    return radii;
}

Matrix6 ShellModel::extrapolated(const string& caller, const Tiling& tiling, double approximateArea, const Vec3& origin,
                                 int maxBeads, int numResolutions) {
    vector<double> sigmas = beadRadii(tiling, approximateArea, maxBeads, numResolutions);
    vector<Matrix6> tensors;
    for (double sigma : sigmas) {
        vector<Vec3> beads = tiling(sigma);
        tensors.push_back(BeadHydrodynamics::resistance(caller, beads, vector<double>(beads.size(), sigma), origin));
    }
    return extrapolateToZeroBeadSize(sigmas, tensors);
}
