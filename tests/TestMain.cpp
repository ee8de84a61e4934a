// Test entry point, linked into every test executable: loads the platform under test (see
// platformUnderTest() in RigidBodyTestUtilities.h) and this build's kernels for it, then runs the
// tests. The order is OpenMM's when it loads a plugin directory: OpenMM's platform library, then
// this plugin's kernel library for it, then the Reference kernels (linked in: Reference is every
// platform's peer), which also go on a platform derived from ReferencePlatform (CPU) for the
// kernels it lacks.
//
// A platform that does not load stops the tests with the error, rather than letting them pass
// without testing it (OpenCL runs on PoCL, installed by scripts/setup.sh). Only CUDA may be absent,
// and only where NVIDIA's driver is (libcuda.so): its tests then say so, and ctest reports them as
// skipped.
#include "RigidBodyTestUtilities.h"
#include <gtest/gtest.h>
#include <iostream>

extern "C" void registerRigidLangevinReferenceKernelFactories();

using namespace RigidBodyTest;

namespace {

/** Loads a plugin library; on failure returns its error, else "". */
std::string load(const std::string& path) {
    try {
        OpenMM::Platform::loadPluginLibrary(path);
    }
    catch (const std::exception& e) {
        return path+": "+e.what();
    }
    return "";
}

bool present(const std::string& name) {
    for (int i = 0; i < OpenMM::Platform::getNumPlatforms(); i++)
        if (OpenMM::Platform::getPlatform(i).getName() == name)
            return true;
    return false;
}

} // namespace

int main(int argc, char** argv) {
    const PlatformUnderTest& platform = platformUnderTest();
    std::string openmmFailure;
    if (!platform.openmmLibrary.empty()) {
        // The CPU platform computes PME reciprocal space through OpenMM's PME plugin.
        if (platform.name == "CPU")
            openmmFailure = load(std::string(OPENMM_PLUGIN_DIR)+"/libOpenMMPME.so");
        if (openmmFailure.empty())
            openmmFailure = load(std::string(OPENMM_PLUGIN_DIR)+"/"+platform.openmmLibrary);
    }
    if (!present(platform.name)) {
        if (platform.mayBeMissing && openmmFailure.find("libcuda.so") != std::string::npos) {
            std::cout << platform.name << " platform not available: skipped (no NVIDIA driver here)" << std::endl;
            return 0;
        }
        std::cerr << "OpenMM's " << platform.name << " platform did not load; the tests need it. " << openmmFailure << std::endl;
        return 1;
    }
    if (!platform.pluginLibrary.empty()) {
        std::string failure = load(std::string(RIGIDLANGEVIN_BUILD_DIR)+"/"+platform.pluginLibrary);
        if (!failure.empty()) {
            std::cerr << "The plugin's kernels for the " << platform.name << " platform did not load. " << failure << std::endl;
            return 1;
        }
    }
    registerRigidLangevinReferenceKernelFactories();
    if (!OpenMM::Platform::getPlatformByName(platform.name).supportsKernels({RigidLangevinPlugin::IntegrateRigidLangevinStepKernel::Name()})) {
        std::cerr << "OpenMM's " << platform.name << " platform is present but the plugin's kernels for it are not registered" << std::endl;
        return 1;
    }
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
