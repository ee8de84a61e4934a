#ifndef COMMON_ARRAYS_H_
#define COMMON_ARRAYS_H_

#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include <algorithm>
#include <string>

namespace RigidLangevinPlugin {

/** How fitArray() sizes an array that exists: to the size asked, or kept while it holds at least that. */
enum class ArrayFit {Exact, AtLeast};

/**
 * Give array size elements of elementSize bytes (at least one), initialising it on first use and
 * resizing it later: bodies are set up again (checkpoints) and blobs and grids with each
 * configuration, where AtLeast keeps memory that a smaller configuration still fits. True if the
 * array was (re)allocated, when its contents are undefined.
 */
inline bool fitArray(OpenMM::ComputeContext& cc, OpenMM::ComputeArray& array, size_t size, int elementSize, const std::string& name, ArrayFit fit) {
    size = std::max(size, (size_t) 1);
    if (!array.isInitialized())
        array.initialize(cc, size, elementSize, name);
    else if (array.getSize() < size || (fit == ArrayFit::Exact && array.getSize() != size))
        array.resize(size);
    else
        return false;
    return true;
}

} // namespace RigidLangevinPlugin

#endif /*COMMON_ARRAYS_H_*/
