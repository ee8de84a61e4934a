#ifndef RIGID_LANGEVIN_PSE_WAVE_SPACE_H_
#define RIGID_LANGEVIN_PSE_WAVE_SPACE_H_

#include "internal/PseFft.h"
#include "internal/PseGaussianGrid.h"
#include "internal/PseParameters.h"
#include <functional>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The wave-space part of the positively split Ewald mobility (Lindbo & Tornberg's spectral Ewald
 * applied to Hasimoto's split, Fiore et al. 2017):
 *
 *   M_wave = (V/N^2) W^T F^H D F W,   D(k) = phi(k) e^{sigma^2 k^2} sinc(k a_i) sinc(k a_j) (I - kk)/k^2,
 *
 * W the Gaussian spreading (PseGaussianGrid), F the grid's discrete Fourier transform (N points,
 * PseFft): the Gaussian's transform e^{-sigma^2 k^2/2} on each side and the factor e^{sigma^2 k^2}
 * between make Hasimoto's weight phi. D is Hermitian positive semidefinite mode by mode, so M_wave
 * is positive semidefinite and has the square root (V^1/2/N) W^T F^H D^1/2 applied to complex
 * white noise. The k = 0 mode (the fluid at rest on average) and the Nyquist planes of even grids
 * (whose k is ambiguous; phi is negligible there) are left out.
 *
 * Blobs of several radii: each radius group is spread and transformed on its own and summed with
 * its sinc(k a); the result is transformed back once per group, times that group's sinc.
 */
class PseWaveSpace {
public:
    typedef KrylovSolvers::ParallelFor ParallelFor;
    typedef std::complex<double> Complex;
    /** Blob i is of radius groupRadii[group[i]]. */
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<int>& group, const std::vector<double>& groupRadii,
                  const OpenMM::Vec3 box[3], const PseParameters& parameters, const ParallelFor& parallel);
    /** out = M_wave f. */
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const ParallelFor& parallel);
    /** out = a sample of covariance M_wave, from getNumNormals() standard normals drawn by normal(). */
    void sampleNoise(const std::function<double()>& normal, Eigen::VectorXd& out, const ParallelFor& parallel);
    /** 3 (N' - 1), N' the grid's points off the Nyquist planes: 6 per independent mode. */
    long long getNumNormals() const;
    // What a device needs to apply the same operator (CommonPseMobility), after setBlobs():
    const PseGaussianGrid& getGaussians() const {
        return gaussians;
    }
    /** Per mode of the half spectrum (M0 x M1 x (M2/2 + 1), the last fastest), D(k) without the
     *  projection; with one radius group times sinc(k a)^2; 0 for the modes left out. */
    const std::vector<double>& getFactors() const {
        return factor;
    }
    /** With several radius groups, sinc(k a_g) per group, then per mode as getFactors(). */
    const std::vector<double>& getSincs() const {
        return sincs;
    }
    /** The reciprocal box vectors times 2 pi: mode (i0, i1, i2) has k = sum_d n_d reciprocal_d, n_d its signed frequency. */
    const OpenMM::Vec3& getReciprocal(int d) const {
        return reciprocal[d];
    }
private:
    /** The mode (i0, i1, i2) of the half spectrum: its wave vector, and false for k = 0 or a Nyquist plane. */
    bool waveVector(int i0, int i1, int i2, OpenMM::Vec3& k) const;
    void computeFactors(const std::vector<double>& groupRadii, double volume, double sigma, double xi, const ParallelFor& parallel);
    /** spectrum(k) = D(k) (I - kk) spectrum(k) for every mode. */
    void applyFactors(Complex* spectrum, const ParallelFor& parallel) const;
    /** to(k) = sinc(k a_g) from(k), or to += that if add. */
    void scaleBySinc(int g, const Complex* from, Complex* to, bool add, const ParallelFor& parallel) const;
    /** The complex white noise, projected and scaled by D^1/2, into spectrum. */
    void drawSpectrum(const std::function<double()>& normal);
    /** From a spectrum already scaled by D (times sinc for one group) to out, each group's blobs. */
    void backToBlobs(Eigen::VectorXd& out, const ParallelFor& parallel);
    PseGaussianGrid gaussians;
    PseFft fft;
    int grid[3], numGroups, numBlobs;
    OpenMM::Vec3 reciprocal[3];
    std::vector<double> factor, sincs, factorKey;
    std::vector<double> real;
    std::vector<Complex> spectrum, summed;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PSE_WAVE_SPACE_H_*/
