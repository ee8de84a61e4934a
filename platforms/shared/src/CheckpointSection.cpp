#include "internal/CheckpointSection.h"
#include "openmm/OpenMMException.h"
#include <cstdint>
#include <cstring>
#include <zlib.h>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;
using std::string;

namespace {

const char Magic[4] = {'R', 'L', 'c', 'k'};

/** zlib's CRC-32 of a buffer longer than its uInt length argument can say at once. */
uint32_t checksum(uint32_t crc, const char* data, uint64_t size) {
    while (size > 0) {
        uInt chunk = (uInt) std::min<uint64_t>(size, 1u << 30);
        crc = (uint32_t) crc32(crc, (const Bytef*) data, chunk);
        data += chunk;
        size -= chunk;
    }
    return crc;
}

/** The CRC-32 a frame stores: of its version, its length and its payload, as written. */
uint32_t frameChecksum(int32_t version, uint64_t length, const string& payload) {
    char header[sizeof(version)+sizeof(length)];
    memcpy(header, &version, sizeof(version));
    memcpy(header+sizeof(version), &length, sizeof(length));
    return checksum(checksum(crc32(0, Z_NULL, 0), header, sizeof(header)), payload.data(), payload.size());
}

OpenMMException damaged(const string& why, const string& integrator) {
    return OpenMMException(integrator+": the checkpoint is damaged ("+why+"): the rigid bodies' part of it cannot be trusted, and "
                           "it was not loaded. Load an undamaged copy");
}

} // namespace

void CheckpointSection::write(std::ostream& stream, const string& payload) {
    int32_t version = CurrentVersion;
    uint64_t length = payload.size();
    uint32_t crc = frameChecksum(version, length, payload);
    stream.write(Magic, sizeof(Magic));
    stream.write((const char*) &crc, sizeof(crc));
    stream.write((const char*) &version, sizeof(version));
    stream.write((const char*) &length, sizeof(length));
    stream.write(payload.data(), payload.size());
}

string CheckpointSection::read(std::istream& stream, int& version, const string& integrator) {
    char start[4];
    stream.read(start, sizeof(start));
    if (!stream)
        throw damaged("it ends before the rigid bodies' part", integrator);
    if (memcmp(start, Magic, sizeof(Magic)) != 0) {
        int32_t unframed;
        memcpy(&unframed, start, sizeof(unframed));
        if (unframed == UnframedVersion) {
            version = UnframedVersion;
            return string();
        }
        throw OpenMMException(integrator+": the checkpoint's rigid-body part is not one this plugin reads (it is damaged, or was "
                              "written by a version of the plugin older than format 3 or newer than format "+std::to_string(CurrentVersion)+")");
    }
    uint32_t stored;
    int32_t written;
    uint64_t length;
    stream.read((char*) &stored, sizeof(stored));
    stream.read((char*) &written, sizeof(written));
    stream.read((char*) &length, sizeof(length));
    if (!stream)
        throw damaged("it ends inside the rigid bodies' header", integrator);
    // Read in pieces, so that a damaged length cannot ask for more memory than the stream holds.
    string payload;
    const uint64_t piece = 1 << 20;
    while (payload.size() < length) {
        uint64_t start = payload.size(), count = std::min(piece, length-start);
        payload.resize(start+count);
        stream.read(&payload[start], count);
        if (!stream)
            throw damaged("it ends "+std::to_string(length-start-stream.gcount())+" bytes before the end its header gives", integrator);
    }
    if (frameChecksum(written, length, payload) != stored)
        throw damaged("its CRC-32 does not match its contents", integrator);
    if (written != CurrentVersion)
        throw OpenMMException(integrator+": the checkpoint's rigid-body part has format "+std::to_string(written)+
                              ", which this version of the plugin (format "+std::to_string(CurrentVersion)+") does not read");
    version = written;
    return payload;
}
