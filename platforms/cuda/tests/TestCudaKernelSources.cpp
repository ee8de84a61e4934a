/*
 * The common platforms' device source compiles for CUDA, in every precision, exactly as the CUDA
 * platform would compile it (StickyDipoleForce's pair term inside a stand-in for OpenMM's
 * nonbonded kernel, which declares what that kernel gives it; the blobs' mobility kernels of hydrodynamic interactions, tiled
 * and positively split Ewald): OpenMM's own CUDA prelude (CudaKernelSources::common and vectorOps,
 * read from libOpenMMCUDA), the precision's types, the plugin's definitions and source, through
 * NVRTC. NVRTC needs no GPU, so this runs wherever the CUDA toolkit is installed; the tests that
 * run the CUDA platform (the other runners in this directory) need a GPU.
 *
 * The step kernels must also keep every per-body array in registers: NVRTC's PTX may declare no
 * local memory (.local) in them. 97e1b74 brought the step kernel from 1329 to 653 bytes per
 * body-step on an H100 by that alone, and a loop with a runtime bound over an array (the random
 * numbers' with randomPerBody as its bound, say) puts the array back in local memory.
 *
 * libOpenMMCUDA is opened with the CUDA driver library present; without a driver the build points
 * it to the toolkit's stub (platforms/cuda/tests/CMakeLists.txt), which is enough to read its strings. The test
 * is skipped only where OpenMM's CUDA platform library is not installed at all; one that is there
 * but cannot be opened, or lacks the prelude, is a failure.
 */
#include "RigidBodyKernelLayout.h"
#include "CommonRigidLangevinKernelSources.h"
#include <dlfcn.h>
#include <unistd.h>
#include <gtest/gtest.h>
#include <map>
#include <nvrtc.h>
#include <sstream>
#include <string>
#include <vector>

using namespace RigidLangevinPlugin;

namespace {

/** OpenMM's CUDA prelude strings, from the platform library. */
struct CudaPrelude {
    const std::string* common = nullptr;
    const std::string* vectorOps = nullptr;
    bool installed = false;
    std::string error;
};

CudaPrelude loadPrelude() {
    CudaPrelude prelude;
    std::string path = std::string(OPENMM_PLUGIN_DIR)+"/libOpenMMCUDA.so";
    prelude.installed = (access(path.c_str(), F_OK) == 0);
    if (!prelude.installed) {
        prelude.error = path+" is not installed";
        return prelude;
    }
    void* library = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (library == nullptr) {
        prelude.error = dlerror();
        return prelude;
    }
    prelude.common = static_cast<const std::string*>(dlsym(library, "_ZN6OpenMM17CudaKernelSources6commonB5cxx11E"));
    prelude.vectorOps = static_cast<const std::string*>(dlsym(library, "_ZN6OpenMM17CudaKernelSources9vectorOpsB5cxx11E"));
    if (prelude.common == nullptr || prelude.vectorOps == nullptr)
        prelude.error = "libOpenMMCUDA has no CudaKernelSources::common or ::vectorOps";
    return prelude;
}

/**
 * StickyDipoleForce's pair term in a kernel that declares what OpenMM's nonbonded kernel gives it
 * (atom1, atom2, posq1, posq2, delta, r2, r, invR, isExcluded, interactionScale, tempEnergy, the
 * per-atom parameters), its placeholders defined as CommonCalcStickyDipoleForceKernel replaces them.
 */
std::string stickyDipolePairKernel() {
    std::ostringstream src;
    src << "#define SITE_X1 x1\n#define SITE_X2 x2\n#define SITE_Y1 y1\n#define SITE_Y2 y2\n#define TYPE_PARAMS types\n";
    src << "#define GRADIENTS gradients\n#define TYPE_STRIDE 10\n#define IS_EXCLUDED isExcluded\n#define USE_SWITCH 1\n";
    src << "#define SWITCH_LOWER ((real) 0.8)\n#define SWITCH_UPPER ((real) 0.9)\n#define COULOMB ((real) 138.9)\n#define KAPPA ((real) 0.6)\n";
    src << "#define THREE_FIFTHS ((real) 0.6)\n#define FOUR_FIFTHS ((real) 0.8)\n#define ONE_FIFTH ((real) 0.2)\n";
    src << "#define USE_CUTOFF 1\n#define CUTOFF_SQUARED ((real) 0.81)\n#define INCLUDE_FORCES 1\n";
    src << "extern \"C\" __global__ void stickyDipolePair(const real4* posq, const real4* xAxis, const real4* yAxis, const real* types,\n"
           "        unsigned long long* gradients, mixed* energyBuffer) {\n"
           "    unsigned int atom1 = threadIdx.x, atom2 = blockIdx.x;\n"
           "    real4 posq1 = posq[atom1], posq2 = posq[atom2];\n"
           "    real4 x1 = xAxis[atom1], x2 = xAxis[atom2], y1 = yAxis[atom1], y2 = yAxis[atom2];\n"
           "    real3 delta = make_real3(posq2.x-posq1.x, posq2.y-posq1.y, posq2.z-posq1.z);\n"
           "    real r2 = dot(delta, delta), invR = RSQRT(r2), r = r2*invR;\n"
           "    bool isExcluded = false;\n"
           "    const real interactionScale = 1;\n"
           "    real tempEnergy = 0;\n";
    src << CommonRigidLangevinKernelSources::stickyDipolePair << "\n";
    src << "    energyBuffer[atom1] += tempEnergy;\n}\n";
    return src.str();
}

/** The source CudaContext::compileProgram builds for the plugin's kernels in one precision and scheme. */
std::string compositeSource(const CudaPrelude& prelude, const std::string& precision, RigidLangevinIntegrator::Scheme scheme) {
    bool doublePrecision = (precision == "double"), mixedIsDouble = (precision != "single");
    std::string real = (doublePrecision ? "double" : "float"), mixed = (mixedIsDouble ? "double" : "float");
    std::ostringstream src;
    if (precision == "double")
        src << "#define USE_DOUBLE_PRECISION 1\n";
    if (precision == "mixed")
        src << "#define USE_MIXED_PRECISION 1\n";
    for (int n = 2; n <= 4; n++) {
        src << "#define make_real" << n << " make_" << real << n << "\n";
        src << "#define make_mixed" << n << " make_" << mixed << n << "\n";
    }
    src << "typedef " << real << " real;\ntypedef " << real << "2 real2;\ntypedef " << real << "3 real3;\ntypedef " << real << "4 real4;\n";
    src << "typedef " << mixed << " mixed;\ntypedef " << mixed << "2 mixed2;\ntypedef " << mixed << "3 mixed3;\ntypedef " << mixed << "4 mixed4;\n";
    src << "typedef unsigned int tileflags;\n";
    // CudaContext's math defines (those the plugin's source uses).
    src << "#define SQRT " << (doublePrecision ? "sqrt" : "sqrtf") << "\n#define RSQRT " << (doublePrecision ? "rsqrt" : "rsqrtf") << "\n";
    src << *prelude.common << "\n";
    for (auto& define : RigidBodyKernelLayout::defines(1024, mixedIsDouble, scheme))
        src << "#define " << define.first << " " << define.second << "\n";
    src << *prelude.vectorOps << RigidBodyKernelLayout::source() << "\n";
    src << CommonRigidLangevinKernelSources::stickyDipoleSites << "\n";
    src << stickyDipolePairKernel() << "\n";
    // The blobs' product with its pair terms in single precision (CommonBlobMobility at loose
    // tolerances) in the single-precision composite, in double in the others.
    src << "#define BLOB_TILE 64\n#define PAIR_SINGLE " << (precision == "single" ? 1 : 0) << "\n" << CommonRigidLangevinKernelSources::blobMobility << "\n";
    // The positively split Ewald product (CommonPseMobility), its real-space pairs in double in the double composite.
    src << "#define PSE_DOUBLE_PAIRS " << (precision == "double" ? 1 : 0) << "\n" << CommonRigidLangevinKernelSources::pseMobility << "\n";
    return src.str();
}

/**
 * The step kernels (entries named step*) in a PTX module, each with its local-memory declarations
 * (arrays the compiler could not keep in registers), empty where it has none.
 */
std::map<std::string, std::string> stepKernelLocalMemory(const std::string& ptx) {
    std::map<std::string, std::string> kernels;
    std::istringstream lines(ptx);
    std::string line, current;
    while (std::getline(lines, line)) {
        size_t entry = line.find(".entry ");
        if (entry != std::string::npos) {
            std::string name = line.substr(entry+7, line.find('(', entry)-entry-7);
            current = (name.compare(0, 4, "step") == 0 ? name : "");
            if (!current.empty())
                kernels[current];
        }
        else if (line.find(".func") != std::string::npos && line.find("call") == std::string::npos)
            current = "";  // a device function's own body (CUDA's slow path of sin and cos has one)
        else if (!current.empty() && line.find(".local .align") != std::string::npos)
            kernels[current] += line.substr(line.find_first_not_of(" \t"))+"\n";  // e.g. ".local .align 16 .b8 __local_depot5[96];"
    }
    return kernels;
}

} // namespace

TEST(CudaKernelSources, CompileInEveryPrecisionAndScheme) {
    CudaPrelude prelude = loadPrelude();
    if (!prelude.installed)
        GTEST_SKIP() << "CUDA kernel compilation check not possible: " << prelude.error;
    ASSERT_TRUE(prelude.error.empty()) << "OpenMM's CUDA platform library is installed but unusable: " << prelude.error;
    for (std::string precision : {"single", "mixed", "double"})
    for (RigidLangevinIntegrator::Scheme scheme : {RigidLangevinIntegrator::ExactFlow, RigidLangevinIntegrator::BAOAB, RigidLangevinIntegrator::Original}) {
        SCOPED_TRACE(precision+" precision, scheme "+std::to_string((int) scheme));
        std::string source = compositeSource(prelude, precision, scheme);
        nvrtcProgram program;
        ASSERT_EQ(NVRTC_SUCCESS, nvrtcCreateProgram(&program, source.c_str(), "rigidLangevin.cu", 0, nullptr, nullptr));
        // The CUDA platform's default options, for the oldest architecture this toolkit supports.
        int numArchs;
        nvrtcGetNumSupportedArchs(&numArchs);
        std::vector<int> archs(numArchs);
        nvrtcGetSupportedArchs(archs.data());
        std::string arch = "-arch=compute_"+std::to_string(archs[0]);
        const char* options[] = {arch.c_str(), "--use_fast_math"};
        nvrtcResult result = nvrtcCompileProgram(program, 2, options);
        size_t logSize;
        nvrtcGetProgramLogSize(program, &logSize);
        std::string log(logSize, '\0');
        nvrtcGetProgramLog(program, &log[0]);
        std::string ptx;
        if (result == NVRTC_SUCCESS) {
            size_t ptxSize;
            nvrtcGetPTXSize(program, &ptxSize);
            ptx.resize(ptxSize);
            nvrtcGetPTX(program, &ptx[0]);
        }
        nvrtcDestroyProgram(&program);
        EXPECT_EQ(NVRTC_SUCCESS, result) << log;
        if (result != NVRTC_SUCCESS)
            continue;
        std::map<std::string, std::string> kernels = stepKernelLocalMemory(ptx);
        EXPECT_EQ((size_t) 7, kernels.size()) << "step kernels found in the PTX";
        for (auto& kernel : kernels)
            EXPECT_EQ("", kernel.second) << kernel.first << " keeps arrays in local memory";
        std::cout << precision << " precision, scheme " << scheme << ": compiled for " << arch << ", " << kernels.size()
                  << " step kernels without local memory" << std::endl;
    }
}
