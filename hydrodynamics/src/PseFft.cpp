#include "internal/PseFft.h"
#define POCKETFFT_NO_MULTITHREADING
#include "pocketfft_hdronly.h"

using namespace RigidLangevinPlugin;

namespace {

/** Byte strides of a grid of shape M0 x M1 x length x 3 with elements of elementBytes. */
pocketfft::stride_t strides(const int grid[3], int length, size_t elementBytes) {
    const ptrdiff_t e = elementBytes;
    return {(ptrdiff_t) grid[1]*length*3*e, (ptrdiff_t) length*3*e, 3*e, e};
}

} // namespace

PseFft::PseFft(const int size[3]) {
    for (int d = 0; d < 3; d++)
        grid[d] = (size == nullptr ? 1 : size[d]);
}

void PseFft::complexAxis(int axis, bool forward, Complex* spectrum, const ParallelFor& parallel) const {
    const int half = halfLength();
    const pocketfft::stride_t stride = strides(grid, half, sizeof(Complex));
    // Split along the other of the first two axes: each thread transforms whole lines.
    const int split = 1-axis;
    parallel(grid[split], [&] (int begin, int end) {
        pocketfft::shape_t shape = {(size_t) grid[0], (size_t) grid[1], (size_t) half, 3};
        shape[split] = end-begin;
        Complex* start = spectrum+(size_t) begin*stride[split]/sizeof(Complex);
        pocketfft::c2c<double>(shape, stride, stride, {(size_t) axis}, forward, start, start, 1.0);
    });
}

void PseFft::forward(const double* real, Complex* spectrum, const ParallelFor& parallel) const {
    const int half = halfLength();
    const pocketfft::stride_t realStride = strides(grid, grid[2], sizeof(double)), complexStride = strides(grid, half, sizeof(Complex));
    parallel(grid[0], [&] (int begin, int end) {
        const pocketfft::shape_t shape = {(size_t) (end-begin), (size_t) grid[1], (size_t) grid[2], 3};
        pocketfft::r2c<double>(shape, realStride, complexStride, 2, pocketfft::FORWARD, real+(size_t) begin*grid[1]*grid[2]*3,
                               spectrum+(size_t) begin*grid[1]*half*3, 1.0);
    });
    complexAxis(1, pocketfft::FORWARD, spectrum, parallel);
    complexAxis(0, pocketfft::FORWARD, spectrum, parallel);
}

void PseFft::inverse(Complex* spectrum, double* real, const ParallelFor& parallel) const {
    const int half = halfLength();
    complexAxis(0, pocketfft::BACKWARD, spectrum, parallel);
    complexAxis(1, pocketfft::BACKWARD, spectrum, parallel);
    const pocketfft::stride_t realStride = strides(grid, grid[2], sizeof(double)), complexStride = strides(grid, half, sizeof(Complex));
    parallel(grid[0], [&] (int begin, int end) {
        const pocketfft::shape_t shape = {(size_t) (end-begin), (size_t) grid[1], (size_t) grid[2], 3};
        pocketfft::c2r<double>(shape, complexStride, realStride, 2, pocketfft::BACKWARD, spectrum+(size_t) begin*grid[1]*half*3,
                               real+(size_t) begin*grid[1]*grid[2]*3, 1.0);
    });
}
