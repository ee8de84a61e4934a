#ifndef RIGID_LANGEVIN_CHECKPOINT_SECTION_H_
#define RIGID_LANGEVIN_CHECKPOINT_SECTION_H_

#include "internal/windowsExportRigidLangevin.h"
#include <istream>
#include <ostream>
#include <string>

namespace RigidLangevinPlugin {

/**
 * The plugin's part of an OpenMM checkpoint, framed so that damage is found before anything is
 * read from it: 4 magic bytes "RLck", the CRC-32 (zlib's) of everything after it, the format
 * version, the payload's length in bytes, the payload. Format 3, the last without a frame, began
 * with the version itself (the integer 3) and is still read.
 */
namespace CheckpointSection {

/** The format this plugin writes. */
const int CurrentVersion = 4;
/** The last format without a frame (no magic, no checksum), still read. */
const int UnframedVersion = 3;

/** Write payload as a framed section of the current format. */
OPENMM_EXPORT_RIGIDLANGEVIN void write(std::ostream& stream, const std::string& payload);

/**
 * Read a section. For the current format, returns its payload once its checksum and length hold
 * (version = CurrentVersion); for the unframed format 3, returns an empty string with version =
 * UnframedVersion and the stream at its payload. Throws an OpenMMException for anything else: a
 * damaged or truncated section, or one of a format this plugin does not read, its message begun
 * with the integrator's class name.
 */
OPENMM_EXPORT_RIGIDLANGEVIN std::string read(std::istream& stream, int& version, const std::string& integrator);

} // namespace CheckpointSection

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_CHECKPOINT_SECTION_H_*/
