// Test entry point: loads OpenMM's own platform libraries, then this build's platform kernels of
// the plugin (the Reference kernels are linked in; the others are plugins, loaded from the build
// tree), so tests can run on every platform this machine has.
//
// Reference, CPU and OpenCL (PoCL, installed by setup) must load; CUDA may be missing only where
// NVIDIA's driver is (libcuda.so). Every platform OpenMM does load and this plugin implements must
// get the plugin's kernels: a kernel library that fails to load beside it stops the tests with its
// error, rather than quietly testing fewer platforms. RIGIDLANGEVIN_TEST_PLATFORMS (say "Reference,CPU", as the
// sanitizer build runs) limits the platforms loaded and tested.
#include "RigidLangevinKernels.h"
#include "openmm/Platform.h"
#include <gtest/gtest.h>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>

extern "C" void registerRigidLangevinReferenceKernelFactories();

namespace {

bool wanted(const std::string& platform) {
    const char* only = std::getenv("RIGIDLANGEVIN_TEST_PLATFORMS");
    return only == NULL || (","+std::string(only)+",").find(","+platform+",") != std::string::npos;
}

} // namespace

int main(int argc, char** argv) {
    std::map<std::string, std::string> failures;
    for (const char* library : {"libOpenMMPME.so", "libOpenMMCPU.so", "libOpenMMOpenCL.so", "libOpenMMCUDA.so"}) {
        std::string name(library);
        if ((name.find("OpenCL") != std::string::npos && !wanted("OpenCL")) || (name.find("CUDA") != std::string::npos && !wanted("CUDA")))
            continue;
        try {
            OpenMM::Platform::loadPluginLibrary(std::string(OPENMM_PLUGIN_DIR)+"/"+library);
        }
        catch (const std::exception& e) {
            failures[library] = e.what();
        }
    }
    registerRigidLangevinReferenceKernelFactories();
    for (const char* library : {"libRigidLangevinCPU.so", "libRigidLangevinOpenCL.so", "libRigidLangevinCUDA.so"}) {
        try {
            OpenMM::Platform::loadPluginLibrary(std::string(RIGIDLANGEVIN_BUILD_DIR)+"/"+library);
        }
        catch (const std::exception& e) {
            failures[library] = e.what();
        }
    }
    bool ok = true;
    for (const char* name : {"Reference", "CPU", "OpenCL", "CUDA"}) {
        bool present = false;
        for (int i = 0; i < OpenMM::Platform::getNumPlatforms(); i++)
            if (OpenMM::Platform::getPlatform(i).getName() == name) {
                present = true;
                if (!OpenMM::Platform::getPlatform(i).supportsKernels({RigidLangevinPlugin::IntegrateRigidLangevinStepKernel::Name()})) {
                    std::cerr << "OpenMM's " << name << " platform is present but the plugin's kernels for it did not load" << std::endl;
                    ok = false;
                }
            }
        if (present || !wanted(name))
            continue;
        std::string platform(name);
        if (platform == "CPU" || platform == "OpenCL") {
            std::cerr << "OpenMM's " << name << " platform did not load; the tests need it (OpenCL runs on PoCL, installed by scripts/setup.sh)" << std::endl;
            ok = false;
        }
        else if (platform == "CUDA" && failures["libOpenMMCUDA.so"].find("libcuda.so") == std::string::npos) {
            // Only a machine without NVIDIA's driver may skip CUDA.
            std::cerr << "OpenMM's CUDA platform did not load for another reason than a missing driver" << std::endl;
            ok = false;
        }
    }
    if (!ok) {
        for (auto& f : failures)
            std::cerr << "  " << f.first << ": " << f.second << std::endl;
        return 1;
    }
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
