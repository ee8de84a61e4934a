// Test entry point: loads OpenMM's own platform libraries, then this build's platform kernels of
// the plugin (the Reference kernels are linked in; the others are plugins, loaded from the build
// tree), so tests can run on every platform this machine has.
#include "openmm/Platform.h"
#include <gtest/gtest.h>
#include <string>

extern "C" void registerRigidLangevinReferenceKernelFactories();

int main(int argc, char** argv) {
    for (const char* library : {"libOpenMMPME.so", "libOpenMMCPU.so", "libOpenMMOpenCL.so", "libOpenMMCUDA.so"}) {
        try {
            OpenMM::Platform::loadPluginLibrary(std::string(OPENMM_PLUGIN_DIR)+"/"+library);
        }
        catch (...) {
            // A platform this machine cannot run (no OpenCL runtime, no CUDA driver) is skipped.
        }
    }
    registerRigidLangevinReferenceKernelFactories();
    for (const char* library : {"libRigidLangevinCPU.so", "libRigidLangevinOpenCL.so", "libRigidLangevinCUDA.so"}) {
        try {
            OpenMM::Platform::loadPluginLibrary(std::string(RIGIDLANGEVIN_BUILD_DIR)+"/"+library);
        }
        catch (...) {
            // Not built here, or its OpenMM platform library could not be loaded.
        }
    }
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
