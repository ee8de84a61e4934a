#ifndef RIGID_LANGEVIN_PSE_FFT_H_
#define RIGID_LANGEVIN_PSE_FFT_H_

#include "internal/KrylovSolvers.h"
#include <complex>

namespace RigidLangevinPlugin {

/**
 * Three-dimensional real-to-complex transforms of a grid of three interleaved components (M0 x M1 x
 * M2 x 3, as PseGaussianGrid writes it) by pocketfft, one axis at a time, each axis's batch of
 * one-dimensional transforms shared out by the caller's ParallelFor (pocketfft's own threads are
 * compiled out). The spectrum is the half M0 x M1 x (M2/2 + 1) x 3 that a real grid determines.
 * Neither direction is normalised: forward is sum_x f(x) e^{-ik.x}, inverse sum_k F(k) e^{ik.x}.
 */
class PseFft {
public:
    typedef KrylovSolvers::ParallelFor ParallelFor;
    typedef std::complex<double> Complex;
    explicit PseFft(const int grid[3] = nullptr);
    /** spectrum = the transform of real. */
    void forward(const double* real, Complex* spectrum, const ParallelFor& parallel) const;
    /** real = the inverse transform of the Hermitian spectrum, which is overwritten. */
    void inverse(Complex* spectrum, double* real, const ParallelFor& parallel) const;
    /** M2/2 + 1: the spectrum's length along the last axis. */
    int halfLength() const {
        return grid[2]/2+1;
    }
private:
    /** Transform along axis 0 or 1 of the spectrum, in place. */
    void complexAxis(int axis, bool forward, Complex* spectrum, const ParallelFor& parallel) const;
    int grid[3];
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PSE_FFT_H_*/
