#include "ResistanceTensor.h"
#include "internal/BeadHydrodynamics.h"
#include "internal/PerrinFriction.h"
#include "internal/ResistanceMath.h"
#include "internal/ShellModel.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::ResistanceMath;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

Matrix6 toMatrix(const double* values) {
    return Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> >(values);
}

void fromMatrix6(const Matrix6& m, double* values) {
    Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor> > map(values);
    map = m;
}

vector<double> toVector(const Matrix6& m) {
    vector<double> v(36);
    fromMatrix6(m, v.data());
    return v;
}

} // namespace

ResistanceTensor::ResistanceTensor() {
    for (double& v : values)
        v = 0.0;
}

ResistanceTensor ResistanceTensor::fromMatrix(const vector<double>& matrix, const Vec3& origin) {
    if (matrix.size() != 36)
        throw OpenMMException("ResistanceTensor: a resistance tensor needs 36 values (a 6x6 matrix, row-major), got "+std::to_string(matrix.size()));
    ResistanceTensor t;
    for (int i = 0; i < 36; i++)
        t.values[i] = matrix[i];
    t.origin = origin;
    t.validate("ResistanceTensor");
    return t;
}

ResistanceTensor ResistanceTensor::sphere(double radius, const Vec3& center) {
    if (!(radius > 0) || !std::isfinite(radius))
        throw OpenMMException("ResistanceTensor::sphere: the radius must be positive and finite, got "+std::to_string(radius));
    Matrix6 m = Matrix6::Zero();
    m.block<3, 3>(0, 0) = 6*M_PI*radius*Eigen::Matrix3d::Identity();
    m.block<3, 3>(3, 3) = 8*M_PI*radius*radius*radius*Eigen::Matrix3d::Identity();
    ResistanceTensor t;
    fromMatrix6(m, t.values);
    t.origin = center;
    return t;
}

namespace {

ResistanceTensor diagonal(const PerrinFriction::PrincipalFriction& f, const Vec3& center) {
    vector<double> m(36, 0.0);
    for (int i = 0; i < 3; i++) {
        m[7*i] = f.translation[i];
        m[7*(i+3)] = f.rotation[i];
    }
    return ResistanceTensor::fromMatrix(m, center);
}

Vec3 centroid(const vector<Vec3>& positions) {
    Vec3 sum;
    for (const Vec3& p : positions)
        sum += p;
    return sum/(double) positions.size();
}

void checkBeadRadius(const std::string& caller, double beadRadius) {
    if (!(beadRadius > 0) || !std::isfinite(beadRadius))
        throw OpenMMException(caller+": the shell's bead radius is "+std::to_string(beadRadius)+"; it must be positive and finite (nm)");
}

void checkCenter(const std::string& caller, const Vec3& center) {
    if (!std::isfinite(center[0]) || !std::isfinite(center[1]) || !std::isfinite(center[2]))
        throw OpenMMException(caller+": the centre must have finite coordinates");
}

} // namespace

ResistanceTensor ResistanceTensor::ellipsoid(double a, double b, double c, const Vec3& center) {
    checkCenter("ResistanceTensor::ellipsoid", center);
    return diagonal(PerrinFriction::ellipsoid(a, b, c), center);
}

ResistanceTensor ResistanceTensor::spheroid(double a, double b, const Vec3& center) {
    checkCenter("ResistanceTensor::spheroid", center);
    return diagonal(PerrinFriction::spheroid(a, b), center);
}

ResistanceTensor ResistanceTensor::beads(const vector<Vec3>& positions, const vector<double>& radii, double correctionVolume) {
    const std::string caller = "ResistanceTensor::beads";
    if (!(correctionVolume >= 0) || !std::isfinite(correctionVolume))
        throw OpenMMException(caller+": the correction volume is "+std::to_string(correctionVolume)+"; it must be zero (no correction) or a positive volume (nm^3)");
    BeadHydrodynamics::validate(caller, positions, radii);
    Vec3 origin = centroid(positions);
    Matrix6 xi = BeadHydrodynamics::resistance(caller, positions, radii, origin);
    // The rotational friction of the filled volume, 6 eta V per unit viscosity; it does not
    // depend on the origin, so it can be added here.
    xi.block<3, 3>(3, 3) += 6*correctionVolume*Eigen::Matrix3d::Identity();
    ResistanceTensor t;
    fromMatrix6(xi, t.values);
    t.origin = origin;
    return t;
}

double ResistanceTensor::beadVolume(const vector<double>& radii) {
    double volume = 0;
    for (int i = 0; i < (int) radii.size(); i++) {
        if (!(radii[i] >= 0) || !std::isfinite(radii[i]))
            throw OpenMMException("ResistanceTensor::beadVolume: bead "+std::to_string(i)+" has radius "+std::to_string(radii[i])+"; radii must be non-negative and finite");
        volume += 4*M_PI/3*radii[i]*radii[i]*radii[i];
    }
    return volume;
}

vector<Vec3> ResistanceTensor::roughShellBeads(const vector<Vec3>& positions, const vector<double>& radii, double beadRadius) {
    ShellModel::validateSpheres("ResistanceTensor::roughShellBeads", positions, radii);
    checkBeadRadius("ResistanceTensor::roughShellBeads", beadRadius);
    return ShellModel::tileSphereUnion(positions, radii, beadRadius);
}

vector<Vec3> ResistanceTensor::scaleBlobsToFriction(const vector<Vec3>& blobPositions, const vector<double>& blobRadii, const Vec3& center,
                                                    const ResistanceTensor& target) {
    const std::string caller = "ResistanceTensor::scaleBlobsToFriction";
    BeadHydrodynamics::validate(caller, blobPositions, blobRadii);
    checkCenter(caller, center);
    Matrix6 wanted = toMatrix(target.values);
    const double wantedTrace = wanted.block<3, 3>(0, 0).trace();  // the translational block is the same about any point
    auto scaled = [&](double scale) {
        vector<Vec3> p;
        for (const Vec3& x : blobPositions)
            p.push_back(center+(x-center)*scale);
        return p;
    };
    // The blobs' translational friction grows with their spread: bracket the scale, then regula falsi.
    auto excess = [&](double scale) {
        return BeadHydrodynamics::resistance(caller, scaled(scale), blobRadii, center).block<3, 3>(0, 0).trace()/wantedTrace-1;
    };
    double low = 1, high = 1, fLow = excess(1), fHigh = fLow;
    const double step = 1.25, minScale = 0.1, maxScale = 10;
    while (fLow > 0) {
        high = low;
        fHigh = fLow;
        low /= step;
        if (low < minScale)
            throw OpenMMException(caller+": the blobs resist translation more than the target even drawn in to a tenth of their spread; "
                                  "give smaller blobs (or fewer) for this body");
        fLow = excess(low);
    }
    while (fHigh < 0) {
        low = high;
        fLow = fHigh;
        high *= step;
        if (high > maxScale)
            throw OpenMMException(caller+": the blobs resist translation less than the target even spread out tenfold; give larger "
                                  "blobs (or more) for this body");
        fHigh = excess(high);
    }
    double scale = low;
    int lastMoved = 0;  // -1 low, +1 high
    for (int iteration = 0; iteration < 200 && high-low > 1e-14*high; iteration++) {
        scale = (low*fHigh-high*fLow)/(fHigh-fLow);
        double f = excess(scale);
        if (std::abs(f) < 1e-13)
            break;
        // Illinois: when the same end moves twice, halve the other's value so that it moves too.
        if (f < 0) {
            low = scale;
            fLow = f;
            if (lastMoved == -1)
                fHigh /= 2;
            lastMoved = -1;
        }
        else {
            high = scale;
            fHigh = f;
            if (lastMoved == 1)
                fLow /= 2;
            lastMoved = 1;
        }
    }
    if (std::abs(excess(scale)) > 1e-10)
        throw OpenMMException(caller+": the blobs' friction did not converge to the target's; give blobs that do not overlap as much");
    return scaled(scale);
}

ResistanceTensor ResistanceTensor::roughShell(const vector<Vec3>& positions, const vector<double>& radii, double beadRadius) {
    ShellModel::validateSpheres("ResistanceTensor::roughShell", positions, radii);
    checkBeadRadius("ResistanceTensor::roughShell", beadRadius);
    vector<Vec3> shell = ShellModel::tileSphereUnion(positions, radii, beadRadius);
    ResistanceTensor t;
    t.origin = centroid(positions);
    fromMatrix6(BeadHydrodynamics::resistance("ResistanceTensor::roughShell", shell, vector<double>(shell.size(), beadRadius), t.origin), t.values);
    return t;
}

ResistanceTensor ResistanceTensor::shellExtrapolated(const vector<Vec3>& positions, const vector<double>& radii, int maxBeads, int numResolutions) {
    const std::string caller = "ResistanceTensor::shellExtrapolated";
    ShellModel::validateSpheres(caller, positions, radii);
    ShellModel::Tiling tiling = [&](double sigma) { return ShellModel::tileSphereUnion(positions, radii, sigma); };
    double area = 0;  // the spheres' total area: at least the union's, a fine first guess
    for (double r : radii)
        area += 4*M_PI*r*r;
    ResistanceTensor t;
    t.origin = centroid(positions);
    Matrix6 xi = ShellModel::extrapolated(caller, tiling, area, t.origin, maxBeads, numResolutions);
    // Every shell is positive definite, but a straight line through shells too coarse for the
    // molecule's detail need not be.
    if (Eigen::LLT<Matrix6>(xi).info() != Eigen::Success)
        throw OpenMMException(caller+": the tensor extrapolated to zero bead size is not positive definite: shells of at most "+std::to_string(maxBeads)+
                " beads are too coarse for this molecule; raise maxBeads");
    fromMatrix6(xi, t.values);
    return t;
}

vector<Vec3> ResistanceTensor::spheroidRoughShellBeads(const vector<Vec3>& centers, const vector<Vec3>& axes, const vector<double>& a,
                                                      const vector<double>& b, double beadRadius) {
    return ShellModel::tileSpheroidUnion("ResistanceTensor::spheroidRoughShellBeads", centers, axes, a, b, beadRadius);
}

ResistanceTensor ResistanceTensor::spheroidRoughShell(const vector<Vec3>& centers, const vector<Vec3>& axes, const vector<double>& a,
                                                      const vector<double>& b, double beadRadius) {
    const std::string caller = "ResistanceTensor::spheroidRoughShell";
    vector<Vec3> shell = ShellModel::tileSpheroidUnion(caller, centers, axes, a, b, beadRadius);
    ResistanceTensor t;
    t.origin = centroid(centers);
    fromMatrix6(BeadHydrodynamics::resistance(caller, shell, vector<double>(shell.size(), beadRadius), t.origin), t.values);
    return t;
}

ResistanceTensor ResistanceTensor::spheroidShellExtrapolated(const vector<Vec3>& centers, const vector<Vec3>& axes, const vector<double>& a,
                                                             const vector<double>& b, int maxBeads, int numResolutions) {
    const std::string caller = "ResistanceTensor::spheroidShellExtrapolated";
    ShellModel::validateSpheroids(caller, centers, axes, a, b);
    ShellModel::Tiling tiling = [&](double sigma) { return ShellModel::tileSpheroidUnion(caller, centers, axes, a, b, sigma); };
    double area = 0;  // spheres of the larger semi-axis: at least the union's area, a fine first guess
    for (int i = 0; i < (int) centers.size(); i++)
        area += 4*M_PI*std::max(a[i], b[i])*std::max(a[i], b[i]);
    ResistanceTensor t;
    t.origin = centroid(centers);
    Matrix6 xi = ShellModel::extrapolated(caller, tiling, area, t.origin, maxBeads, numResolutions);
    if (Eigen::LLT<Matrix6>(xi).info() != Eigen::Success)
        throw OpenMMException(caller+": the tensor extrapolated to zero bead size is not positive definite: shells of at most "+std::to_string(maxBeads)+
                " beads are too coarse for these spheroids; raise maxBeads");
    fromMatrix6(xi, t.values);
    return t;
}

ResistanceTensor ResistanceTensor::freeDrainingBeads(const vector<Vec3>& positions, const vector<double>& radii) {
    if (positions.size() != radii.size())
        throw OpenMMException("ResistanceTensor::freeDrainingBeads: got "+std::to_string(positions.size())+" positions but "+std::to_string(radii.size())+" radii");
    if (positions.empty())
        throw OpenMMException("ResistanceTensor::freeDrainingBeads: the bead model is empty");
    // Bead i at r_i from the origin moves with v + omega x r_i = v - skew(r_i) omega and feels
    // -zeta_i times that; summing forces and torques r_i x f_i gives the blocks.
    Eigen::Vector3d origin = toEigen(positions[0]);
    Matrix6 m = Matrix6::Zero();
    for (int i = 0; i < (int) positions.size(); i++) {
        if (!(radii[i] >= 0) || !std::isfinite(radii[i]))
            throw OpenMMException("ResistanceTensor::freeDrainingBeads: bead "+std::to_string(i)+" has radius "+std::to_string(radii[i])+"; radii must be finite and non-negative");
        if (radii[i] == 0)
            continue;
        double zeta = 6*M_PI*radii[i];
        Eigen::Matrix3d u = skew(toEigen(positions[i])-origin);
        m.block<3, 3>(0, 0) += zeta*Eigen::Matrix3d::Identity();
        m.block<3, 3>(3, 0) += zeta*u;
        m.block<3, 3>(0, 3) -= zeta*u;
        m.block<3, 3>(3, 3) -= zeta*u*u;
    }
    ResistanceTensor t;
    fromMatrix6(m, t.values);
    t.origin = positions[0];
    return t;
}

vector<double> ResistanceTensor::getMatrix(const Vec3& point) const {
    return toVector(moveOrigin(toMatrix(values), toEigen(point-origin)));
}

vector<double> ResistanceTensor::getMatrix() const {
    return vector<double>(values, values+36);
}

Vec3 ResistanceTensor::getCenterOfResistance() const {
    return origin+toVec3(centerOfResistance(toMatrix(values)));
}

Vec3 ResistanceTensor::getCenterOfDiffusion() const {
    Matrix6 xi = toMatrix(values);
    if (xi.llt().info() != Eigen::Success)
        throw OpenMMException("ResistanceTensor::getCenterOfDiffusion: the resistance tensor is singular (is the body linear, or the tensor empty?), so it has no diffusion tensor");
    return origin+toVec3(centerOfDiffusion(xi));
}

vector<double> ResistanceTensor::getDiffusionTensor(double temperature, double viscosity) const {
    return getDiffusionTensor(temperature, viscosity, origin);
}

vector<double> ResistanceTensor::getDiffusionTensor(double temperature, double viscosity, const Vec3& point) const {
    const std::string caller = "ResistanceTensor::getDiffusionTensor";
    if (!(temperature > 0) || !std::isfinite(temperature))
        throw OpenMMException(caller+": the temperature is "+std::to_string(temperature)+"; it must be positive and finite (K)");
    if (!(viscosity > 0) || !std::isfinite(viscosity))
        throw OpenMMException(caller+": the viscosity is "+std::to_string(viscosity)+"; it must be positive and finite (amu/(nm ps); 1 cP = 602.214)");
    Matrix6 xi = moveOrigin(toMatrix(values), toEigen(point-origin));
    Eigen::LLT<Matrix6> llt(xi);
    if (!xi.allFinite() || llt.info() != Eigen::Success)
        throw OpenMMException(caller+": the resistance tensor is not positive definite (is the body linear, with no friction about its axis, or the tensor empty?), so its diffusion tensor is infinite");
    Matrix6 d = llt.solve((BOLTZ*temperature/viscosity)*Matrix6::Identity());
    return toVector(0.5*(d+d.transpose()));
}

ResistanceTensor ResistanceTensor::rotated(const vector<double>& rotation) const {
    if (rotation.size() != 9)
        throw OpenMMException("ResistanceTensor::rotated: a rotation needs 9 values (3x3, row-major)");
    Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> >(rotation.data());
    if ((r*r.transpose()-Eigen::Matrix3d::Identity()).norm() > 1e-8 || r.determinant() < 0)
        throw OpenMMException("ResistanceTensor::rotated: the matrix is not a proper rotation (orthogonal, determinant +1)");
    ResistanceTensor t;
    fromMatrix6(rotate(toMatrix(values), r), t.values);
    t.origin = toVec3(r*toEigen(origin));
    return t;
}

ResistanceTensor ResistanceTensor::translated(const Vec3& displacement) const {
    ResistanceTensor t = *this;
    t.origin += displacement;
    return t;
}

ResistanceTensor ResistanceTensor::scaled(double factor) const {
    ResistanceTensor t = *this;
    for (double& v : t.values)
        v *= factor;
    return t;
}

void ResistanceTensor::validate(const std::string& what) const {
    Matrix6 m = toMatrix(values);
    if (!m.allFinite())
        throw OpenMMException(what+": the resistance tensor contains NaN or infinite values");
    double scale = m.cwiseAbs().maxCoeff();
    if ((m-m.transpose()).cwiseAbs().maxCoeff() > 1e-8*scale)
        throw OpenMMException(what+": the resistance tensor is not symmetric; (force, torque) = -viscosity*Xi*(velocity, angular velocity) needs Xi = Xi^T");
    Eigen::LLT<Matrix6> llt(0.5*(m+m.transpose()));
    if (scale == 0 || llt.info() != Eigen::Success)
        throw OpenMMException(what+": the resistance tensor is not positive definite; every rigid motion must dissipate energy");
}

double ResistanceTensor::unionVolume(const vector<Vec3>& positions, const vector<double>& radii) {
    if (positions.size() != radii.size() || positions.empty())
        throw OpenMMException("ResistanceTensor::unionVolume: needs as many radii as positions, and at least one sphere");
    // Along each line parallel to x through a grid of (y, z) columns the spheres cover a union of
    // intervals whose length is exact; the midpoint rule over the columns then integrates a
    // continuous function, accurate to about 0.1% with ~40 columns across the smallest sphere.
    double lowY = positions[0][1], highY = lowY, lowZ = positions[0][2], highZ = lowZ, smallest = radii[0];
    for (int i = 0; i < (int) positions.size(); i++) {
        if (!(radii[i] > 0) || !std::isfinite(radii[i]))
            throw OpenMMException("ResistanceTensor::unionVolume: sphere "+std::to_string(i)+" has radius "+std::to_string(radii[i])+"; radii must be positive and finite");
        lowY = std::min(lowY, positions[i][1]-radii[i]);
        highY = std::max(highY, positions[i][1]+radii[i]);
        lowZ = std::min(lowZ, positions[i][2]-radii[i]);
        highZ = std::max(highZ, positions[i][2]+radii[i]);
        smallest = std::min(smallest, radii[i]);
    }
    double spacing = std::max(smallest/40, std::max(highY-lowY, highZ-lowZ)/600);
    int ny = (int) std::ceil((highY-lowY)/spacing), nz = (int) std::ceil((highZ-lowZ)/spacing);
    vector<vector<std::pair<double, double> > > columns((size_t) ny*nz);
    for (int i = 0; i < (int) positions.size(); i++) {
        double r2 = radii[i]*radii[i];
        int y0 = std::max(0, (int) std::floor((positions[i][1]-radii[i]-lowY)/spacing));
        int y1 = std::min(ny-1, (int) std::floor((positions[i][1]+radii[i]-lowY)/spacing));
        int z0 = std::max(0, (int) std::floor((positions[i][2]-radii[i]-lowZ)/spacing));
        int z1 = std::min(nz-1, (int) std::floor((positions[i][2]+radii[i]-lowZ)/spacing));
        for (int y = y0; y <= y1; y++)
            for (int z = z0; z <= z1; z++) {
                double dy = lowY+(y+0.5)*spacing-positions[i][1], dz = lowZ+(z+0.5)*spacing-positions[i][2];
                double h2 = r2-dy*dy-dz*dz;
                if (h2 > 0) {
                    double h = std::sqrt(h2);
                    columns[(size_t) y*nz+z].push_back(std::make_pair(positions[i][0]-h, positions[i][0]+h));
                }
            }
    }
    double area = 0;
    for (vector<std::pair<double, double> >& intervals : columns) {
        if (intervals.empty())
            continue;
        std::sort(intervals.begin(), intervals.end());
        double start = intervals[0].first, end = intervals[0].second;
        for (const std::pair<double, double>& interval : intervals) {
            if (interval.first > end) {
                area += end-start;
                start = interval.first;
            }
            end = std::max(end, interval.second);
        }
        area += end-start;
    }
    return area*spacing*spacing;
}
