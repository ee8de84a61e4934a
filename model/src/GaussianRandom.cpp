#include "internal/GaussianRandom.h"
#include "openmm/internal/OSRngSeed.h"
#include <cmath>
#include <istream>
#include <ostream>

using namespace RigidLangevinPlugin;

GaussianRandom::GaussianRandom(int seed) : sfmt(new OpenMM_SFMT::SFMT()), haveSpare(false), spare(0) {
    OpenMM_SFMT::init_gen_rand(seed == 0 ? (uint32_t) osrngseed() : (uint32_t) seed, *sfmt);
}

double GaussianRandom::next() {
    if (haveSpare) {
        haveSpare = false;
        return spare;
    }
    double x, y, r2;
    do {
        x = 2.0*OpenMM_SFMT::genrand_real2(*sfmt)-1.0;
        y = 2.0*OpenMM_SFMT::genrand_real2(*sfmt)-1.0;
        r2 = x*x+y*y;
    } while (r2 >= 1.0 || r2 == 0.0);
    double multiplier = std::sqrt(-2.0*std::log(r2)/r2);
    spare = y*multiplier;
    haveSpare = true;
    return x*multiplier;
}

void GaussianRandom::createCheckpoint(std::ostream& stream) {
    sfmt->createCheckpoint(stream);
    stream.write((char*) &haveSpare, sizeof(haveSpare));
    stream.write((char*) &spare, sizeof(spare));
}

void GaussianRandom::loadCheckpoint(std::istream& stream) {
    sfmt->loadCheckpoint(stream);
    stream.read((char*) &haveSpare, sizeof(haveSpare));
    stream.read((char*) &spare, sizeof(spare));
}
