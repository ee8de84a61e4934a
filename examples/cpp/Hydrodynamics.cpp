// The hydrodynamics library alone, without the integrator or a Context: the translational
// diffusion constant of a water-sized sphere and of a prolate spheroid in water at 300 K, from
// their resistance tensors. Build against libRigidLangevinHydrodynamics and libOpenMM (see docs/install.md).
#include "ResistanceTensor.h"
#include <cmath>
#include <cstdio>

int main() {
    using RigidLangevinPlugin::ResistanceTensor;
    const double temperature = 300, viscosity = 536.0;  // K; amu/(nm ps) = 0.89 cP
    const double boltzmann = 0.00831446261815324;     // kJ/(mol K), as OpenMM has it
    try {
        ResistanceTensor sphere = ResistanceTensor::sphere(0.14);
        ResistanceTensor rod = ResistanceTensor::spheroid(0.5, 0.1);  // semi-axes: along z, across
        for (auto model : {std::make_pair("sphere, radius 0.14 nm", &sphere), std::make_pair("prolate spheroid 0.5 x 0.1 nm", &rod)}) {
            std::vector<double> d = model.second->getDiffusionTensor(temperature, viscosity);
            double translational = (d[0]+d[7]+d[14])/3;  // nm^2/ps: the mean of the translational block's diagonal
            std::printf("%s: D_t = %.4g nm^2/ps = %.4g cm^2/s\n", model.first, translational, translational*1e-2);
        }
        // Stokes-Einstein for the sphere: kT/(6 pi eta a).
        double stokes = boltzmann*temperature/(6*M_PI*viscosity*0.14);
        std::vector<double> d = sphere.getDiffusionTensor(temperature, viscosity);
        if (std::abs(d[0]/stokes-1) > 1e-12) {
            std::printf("sphere differs from Stokes-Einstein: %.10g against %.10g\n", d[0], stokes);
            return 1;
        }
        std::printf("sphere matches Stokes-Einstein kT/(6 pi eta a) = %.6g nm^2/ps\n", stokes);
        return 0;
    }
    catch (const std::exception& e) {
        std::printf("error: %s\n", e.what());
        return 1;
    }
}
