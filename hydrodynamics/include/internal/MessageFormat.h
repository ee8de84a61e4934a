#ifndef RIGID_LANGEVIN_MESSAGE_FORMAT_H_
#define RIGID_LANGEVIN_MESSAGE_FORMAT_H_

#include "openmm/Vec3.h"
#include <sstream>
#include <string>

namespace RigidLangevinPlugin {

/** Numbers and vectors as the hydrodynamics library's error messages write them (six significant digits). */
namespace MessageFormat {

inline std::string str(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

inline std::string describe(const OpenMM::Vec3& v) {
    return "("+str(v[0])+", "+str(v[1])+", "+str(v[2])+")";
}

} // namespace MessageFormat
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_MESSAGE_FORMAT_H_*/
