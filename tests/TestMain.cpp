// Test entry point: registers this build's Reference kernels (also used by the CPU platform) and
// loads OpenMM's own platform libraries, so tests can run on every platform present.
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
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
