#ifndef ZIGGURAT_GAUSSIAN_RANDOM_H_
#define ZIGGURAT_GAUSSIAN_RANDOM_H_

#include "sfmt/SFMT.h"
#include <cmath>
#include <cstdint>
#include <istream>
#include <ostream>
#include <memory>

namespace RigidLangevinPlugin {

/**
 * Standard normal random numbers by the ziggurat method (Marsaglia and Tsang, J. Stat. Softw. 5(8),
 * 2000, in the form of Doornik's ZIGNOR, 2005, which draws the layer and the value from independent
 * bits), from OpenMM's SFMT generator. The CPU kernel draws up to 24 normal numbers per body and
 * step; this takes about a third of the time of the polar Box-Muller method (GaussianRandom), which
 * needs a logarithm and a square root for every pair. Its state (SFMT's and a buffer of its output)
 * can be checkpointed exactly.
 */
class ZigguratGaussianRandom {
public:
    /** Seed the generator (a seed of 0 is used as given; callers pick nonzero seeds). */
    explicit ZigguratGaussianRandom(uint32_t seed) : sfmt(new OpenMM_SFMT::SFMT()), t(tables()), next32(BufferSize) {
        OpenMM_SFMT::init_gen_rand(seed, *sfmt);
    }
    /** A standard normal number. */
    double next() {
        while (true) {
            // u uniform in (-1, 1) from 53 bits; the layer from 7 other bits of the same two words.
            uint32_t a, b;
            twoWords(a, b);
            double u = 2*(((a >> 5)*67108864.0+(b >> 6)+0.5)*(1.0/9007199254740992.0))-1;
            int layer = (a & 0x1F) | ((b & 0x3) << 5);
            if (std::abs(u) < t.ratio[layer])
                return u*t.x[layer];  // inside the layer's rectangle: 99% of draws
            if (layer == 0)
                return tail(u < 0);
            // In the wedge beside the rectangle: accept under the curve.
            double x = u*t.x[layer];
            double f0 = std::exp(-0.5*(t.x[layer]*t.x[layer]-x*x));
            double f1 = std::exp(-0.5*(t.x[layer+1]*t.x[layer+1]-x*x));
            if (f1+uniform()*(f0-f1) < 1.0)
                return x;
        }
    }
    void createCheckpoint(std::ostream& stream) {
        sfmt->createCheckpoint(stream);
        stream.write((char*) buffer, sizeof(buffer));
        stream.write((char*) &next32, sizeof(next32));
    }
    void loadCheckpoint(std::istream& stream) {
        sfmt->loadCheckpoint(stream);
        stream.read((char*) buffer, sizeof(buffer));
        stream.read((char*) &next32, sizeof(next32));
    }
private:
    static const int NumLayers = 128;
    /** Where the tail starts, and the area of each layer, for 128 layers. */
    static constexpr double TailStart = 3.442619855899;
    static constexpr double LayerArea = 9.91256303526217e-3;
    struct Tables {
        double x[NumLayers+1];   ///< layer edges: x[0] = V/f(R) (the base layer's equivalent width), x[1] = R, x[128] = 0
        double ratio[NumLayers]; ///< x[i+1]/x[i]: the fraction of layer i under the curve everywhere
        Tables() {
            double f = std::exp(-0.5*TailStart*TailStart);
            x[0] = LayerArea/f;
            x[1] = TailStart;
            x[NumLayers] = 0;
            for (int i = 2; i < NumLayers; i++) {
                x[i] = std::sqrt(-2*std::log(LayerArea/x[i-1]+f));
                f = std::exp(-0.5*x[i]*x[i]);
            }
            for (int i = 0; i < NumLayers; i++)
                ratio[i] = x[i+1]/x[i];
        }
    };
    static const Tables& tables() {
        static const Tables t;  // computed once, thread-safe
        return t;
    }
    /**
     * The next 32 random bits. SFMT fills a buffer at a time (fill_array32: its fast path, and no
     * function call per number); the buffer and the position in it are part of the state.
     */
    uint32_t word() {
        if (next32 == BufferSize) {
            OpenMM_SFMT::fill_array32(buffer, BufferSize, *sfmt);
            next32 = 0;
        }
        return buffer[next32++];
    }
    /** The next two words, as two calls of word() give them, with one test of the buffer's end. */
    void twoWords(uint32_t& a, uint32_t& b) {
        if (next32 <= BufferSize-2) {
            a = buffer[next32];
            b = buffer[next32+1];
            next32 += 2;
        }
        else {
            a = word();
            b = word();
        }
    }
    /** Uniform in (0, 1), never 0 (it goes into logarithms). */
    double uniform() {
        return (word()+0.5)*(1.0/4294967296.0);
    }
    /** A sample of the normal tail beyond TailStart (Marsaglia's method), with the given sign. */
    double tail(bool negative) {
        double x, y;
        do {
            x = std::log(uniform())/TailStart;
            y = std::log(uniform());
        } while (-2*y < x*x);
        return (negative ? x-TailStart : TailStart-x);
    }
    /** Words per buffer: a multiple of 4, at least SFMT's 624 (get_min_array_size32). */
    static const int BufferSize = 1024;
    std::unique_ptr<OpenMM_SFMT::SFMT> sfmt;
    const Tables& t;  // the shared tables, looked up once (a function-local static is guarded at every use)
    alignas(16) uint32_t buffer[BufferSize];  // SFMT's fill_array32 writes 128-bit words
    int next32;
};

} // namespace RigidLangevinPlugin

#endif /*ZIGGURAT_GAUSSIAN_RANDOM_H_*/
