#include "internal/PseWaveSpace.h"
#include "internal/HasimotoSplit.h"
#include <algorithm>
#include <cmath>

using namespace RigidLangevinPlugin;
using OpenMM::Vec3;
using std::vector;

namespace {

double sinc(double x) {
    return (std::abs(x) < 1e-4 ? 1-x*x/6 : std::sin(x)/x);
}

/** The signed frequency of index i on an axis of m points. */
int frequency(int i, int m) {
    return (i > m/2 ? i-m : i);
}

} // namespace

void PseWaveSpace::setBlobs(const vector<Vec3>& positions, const vector<int>& group, const vector<double>& groupRadii, const Vec3 box[3],
                            const PseParameters& parameters, const ParallelFor& parallel) {
    numGroups = groupRadii.size();
    numBlobs = positions.size();
    const double volume = box[0].dot(box[1].cross(box[2]));
    for (int d = 0; d < 3; d++) {
        grid[d] = parameters.grid[d];
        reciprocal[d] = box[(d+1)%3].cross(box[(d+2)%3])*(2*M_PI/volume);
    }
    gaussians.setBlobs(positions, group, numGroups, box, parameters, parallel);
    fft = PseFft(grid);
    const size_t points = (size_t) grid[0]*grid[1]*grid[2], modes = (size_t) grid[0]*grid[1]*fft.halfLength();
    real.resize(3*points);
    spectrum.resize(3*modes);
    summed.resize(numGroups > 1 ? 3*modes : 0);
    // The factors depend on the box, the grid, the Gaussian and the radii only: kept while those are.
    vector<double> key = {parameters.xi, parameters.gaussianWidth, (double) grid[0], (double) grid[1], (double) grid[2]};
    for (int d = 0; d < 3; d++)
        key.insert(key.end(), {box[d][0], box[d][1], box[d][2]});
    key.insert(key.end(), groupRadii.begin(), groupRadii.end());
    if (key != factorKey)
        computeFactors(groupRadii, volume, parameters.gaussianWidth, parameters.xi, parallel);
    factorKey = key;
}

bool PseWaveSpace::waveVector(int i0, int i1, int i2, Vec3& k) const {
    const int index[3] = {i0, i1, i2};
    for (int d = 0; d < 3; d++)
        if (grid[d]%2 == 0 && index[d] == grid[d]/2)
            return false;
    if (i0 == 0 && i1 == 0 && i2 == 0)
        return false;
    k = reciprocal[0]*frequency(i0, grid[0])+reciprocal[1]*frequency(i1, grid[1])+reciprocal[2]*i2;
    return true;
}

void PseWaveSpace::computeFactors(const vector<double>& groupRadii, double volume, double sigma, double xi, const ParallelFor& parallel) {
    const int half = fft.halfLength();
    const size_t modes = (size_t) grid[0]*grid[1]*half;
    const double points = (double) grid[0]*grid[1]*grid[2];
    factor.resize(modes);
    sincs.resize(numGroups > 1 ? numGroups*modes : 0);
    parallel(grid[0], [&] (int begin, int end) {
        for (int i0 = begin; i0 < end; i0++)
            for (int i1 = 0; i1 < grid[1]; i1++)
                for (int i2 = 0; i2 < half; i2++) {
                    const size_t index = ((size_t) i0*grid[1]+i1)*half+i2;
                    Vec3 k;
                    const bool used = waveVector(i0, i1, i2, k);
                    const double k2 = k.dot(k), length = std::sqrt(k2);
                    // (V/N^2) phi(k) e^{sigma^2 k^2}/k^2: the unnormalised transforms' N^2, spreading's V/N twice, the sum's 1/V.
                    factor[index] = (used ? volume/(points*points)*HasimotoSplit::weight(k2, xi)*std::exp(sigma*sigma*k2)/k2 : 0.0);
                    if (numGroups == 1)
                        factor[index] *= std::pow(sinc(length*groupRadii[0]), 2);
                    else
                        for (int g = 0; g < numGroups; g++)
                            sincs[g*modes+index] = (used ? sinc(length*groupRadii[g]) : 0.0);
                }
    });
}

void PseWaveSpace::applyFactors(Complex* data, const ParallelFor& parallel) const {
    const int half = fft.halfLength();
    parallel(grid[0], [&] (int begin, int end) {
        for (int i0 = begin; i0 < end; i0++)
            for (int i1 = 0; i1 < grid[1]; i1++)
                for (int i2 = 0; i2 < half; i2++) {
                    const size_t index = ((size_t) i0*grid[1]+i1)*half+i2;
                    Complex* u = data+3*index;
                    const double d = factor[index];
                    if (d == 0) {
                        u[0] = u[1] = u[2] = 0.0;
                        continue;
                    }
                    Vec3 k = reciprocal[0]*frequency(i0, grid[0])+reciprocal[1]*frequency(i1, grid[1])+reciprocal[2]*i2;
                    k /= std::sqrt(k.dot(k));
                    const Complex along = k[0]*u[0]+k[1]*u[1]+k[2]*u[2];
                    for (int c = 0; c < 3; c++)
                        u[c] = d*(u[c]-k[c]*along);
                }
    });
}

void PseWaveSpace::scaleBySinc(int g, const Complex* from, Complex* to, bool add, const ParallelFor& parallel) const {
    const size_t modes = factor.size(), planeModes = modes/grid[0];
    parallel(grid[0], [&] (int begin, int end) {
        for (size_t index = begin*planeModes; index < end*planeModes; index++) {
            const double s = sincs[g*modes+index];
            for (int c = 0; c < 3; c++)
                to[3*index+c] = (add ? to[3*index+c] : 0.0)+s*from[3*index+c];
        }
    });
}

void PseWaveSpace::backToBlobs(Eigen::VectorXd& out, const ParallelFor& parallel) {
    out.resize(3*numBlobs);
    if (numGroups == 1) {
        fft.inverse(spectrum.data(), real.data(), parallel);
        gaussians.interpolate(real.data(), 0, out, parallel);
        return;
    }
    for (int g = 0; g < numGroups; g++) {
        scaleBySinc(g, summed.data(), spectrum.data(), false, parallel);
        fft.inverse(spectrum.data(), real.data(), parallel);
        gaussians.interpolate(real.data(), g, out, parallel);
    }
}

void PseWaveSpace::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const ParallelFor& parallel) {
    if (numGroups == 1) {
        gaussians.spread(f, 0, real.data(), parallel);
        fft.forward(real.data(), spectrum.data(), parallel);
        applyFactors(spectrum.data(), parallel);
    }
    else {
        for (int g = 0; g < numGroups; g++) {
            gaussians.spread(f, g, real.data(), parallel);
            fft.forward(real.data(), spectrum.data(), parallel);
            scaleBySinc(g, spectrum.data(), summed.data(), g > 0, parallel);
        }
        applyFactors(summed.data(), parallel);
    }
    backToBlobs(out, parallel);
}

long long PseWaveSpace::getNumNormals() const {
    long long offNyquist = 1;
    for (int d = 0; d < 3; d++)
        offNyquist *= grid[d]-(grid[d]%2 == 0 ? 1 : 0);
    return 3*(offNyquist-1);
}

void PseWaveSpace::drawSpectrum(const std::function<double()>& normal) {
    // One draw per pair k, -k: every mode with i2 > 0, and on the plane i2 = 0 the half with
    // (n0 > 0) or (n0 = 0, n1 > 0), whose partners are set to the complex conjugate. Each of the
    // three components is (N1 + i N2)/sqrt(2), so E|z|^2 = 1.
    const int half = fft.halfLength();
    std::fill(spectrum.begin(), spectrum.end(), Complex(0.0));
    for (int i0 = 0; i0 < grid[0]; i0++)
        for (int i1 = 0; i1 < grid[1]; i1++)
            for (int i2 = 0; i2 < half; i2++) {
                Vec3 k;
                if (!waveVector(i0, i1, i2, k))
                    continue;
                const int n0 = frequency(i0, grid[0]), n1 = frequency(i1, grid[1]);
                if (i2 == 0 && !(n0 > 0 || (n0 == 0 && n1 > 0)))
                    continue;
                Complex z[3];
                for (int c = 0; c < 3; c++) {
                    const double re = normal();
                    z[c] = Complex(re, normal())*std::sqrt(0.5);
                }
                k /= std::sqrt(k.dot(k));
                const size_t index = ((size_t) i0*grid[1]+i1)*half+i2;
                const Complex along = k[0]*z[0]+k[1]*z[1]+k[2]*z[2];
                const double scale = std::sqrt(factor[index]);
                for (int c = 0; c < 3; c++)
                    spectrum[3*index+c] = scale*(z[c]-k[c]*along);
                if (i2 == 0) {
                    const size_t partner = ((size_t) ((grid[0]-i0)%grid[0])*grid[1]+(grid[1]-i1)%grid[1])*half;
                    for (int c = 0; c < 3; c++)
                        spectrum[3*partner+c] = std::conj(spectrum[3*index+c]);
                }
            }
}

void PseWaveSpace::sampleNoise(const std::function<double()>& normal, Eigen::VectorXd& out, const ParallelFor& parallel) {
    drawSpectrum(normal);
    if (numGroups > 1)
        std::swap(spectrum, summed);
    backToBlobs(out, parallel);
}
