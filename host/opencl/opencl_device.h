// OpenCL platforms and devices: listing, choosing, and building the kernel with an on-disk
// cache of compiled program binaries.
#pragma once

#include <CL/opencl.hpp>

#include <cstdint>
#include <iosfwd>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ray {

struct OpenClDevice {
    int index = 0;  // position in the list --list-devices prints
    cl::Platform platform;
    cl::Device device;
    std::string name, platformName, platformVersion, driverVersion;
    bool isGpu = false, isCpu = false;
    bool isPocl = false;      // the platform is PoCL (Portable Computing Language)
    bool isLlvmpipe = false;  // Mesa's software rasterizer (rusticl with RUSTICL_ENABLE=llvmpipe)
    unsigned computeUnits = 0;
    unsigned nativeFloatWidth = 1;  // CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT: 16 with AVX-512, 8 with AVX2
    uint64_t globalMemory = 0, maxAllocation = 0;

    std::string description() const;  // "NAME (PLATFORM)"
};

// Every device of every platform; empty when there is no OpenCL platform at all. The
// platforms come sorted by name (then vendor, version), each with its devices in its own
// order, so that the indices do not depend on the order the ICD loader found them in
// (readdir order of /etc/OpenCL/vendors).
std::vector<OpenClDevice> enumerateOpenClDevices();

// The devices a --device value names, deterministically:
//   auto  a GPU, else PoCL's CPU device, else another CPU device, else another device;
//   cpu   PoCL's CPU device, else another CPU device;
//   gpu   the first GPU;
//   all   every device;
// each the first of its kind in the list, and none of them ever Mesa's llvmpipe (30-145x
// slower than PoCL, and it silently caps each work-item at 65,535 loop iterations, so
// heavy pixels come out wrong). An index or a list of them ("0,2") takes those devices,
// llvmpipe too (the engine then warns about the cap). Throws DeviceError with advice, naming
// the platforms and devices seen, when none fits.
std::vector<OpenClDevice> selectOpenClDevices(const std::string& selector);

// The warning for a selection that includes llvmpipe, empty for other devices.
std::string llvmpipeWarning(const OpenClDevice& device);

void printOpenClDevices(std::ostream& out);

// Starts OpenCL on a thread of its own: the ICD loader loads the drivers (PoCL, and the LLVM
// it links: about 0.03 s) and they list their devices, so that this overlaps other work such
// as loading the scene; the later calls find it done. Errors are left for those calls to
// report. The thread is joined when the returned object is destroyed.
std::jthread startOpenClInBackground();

// Gives this process a PoCL kernel cache folder of its own, `leaf` inside the usual one
// ($POCL_CACHE_DIR, else ray's cache folder): PoCL's cache is known to break when several
// processes compile into it at once, as the ranks of a distributed render on one machine
// would. Call before the first OpenCL call (PoCL reads the variable when it starts).
void usePrivatePoclCacheFolder(const std::string& leaf);

// The lock under which the PoCL devices of this process build programs (buildKernelProgram)
// and let them go (a PoCL program frees its LLVM modules as it goes): held for a PoCL
// device, empty for any other. With `wait` false it is taken only if it is free.
std::unique_lock<std::mutex> poclCompilerLock(const OpenClDevice& device, bool wait = true);

// For main, with its exit code, as the process ends (its output written): exit's handlers
// destroy LLVM's static objects, and a PoCL device still building its kernel on a thread of
// its own (the frame was done without it) would parse bitcode with them half gone (LLVM
// ERROR: out of memory in UpgradeIntrinsicFunction's static Regex: the corpus on --device
// all with POCL_DEVICES="pthread pthread", once or twice a run). So no build runs past
// this point: while one runs, the process ends at once without those handlers (_Exit, its
// streams flushed); otherwise the builds' lock is kept to the end. Returns the exit code.
int endWithoutPoclBuilds(int exitCode);

struct KernelProgram {
    cl::Context context;
    cl::Program program;
    double buildSeconds = 0;
    bool fromCache = false;
};

// Builds the embedded kernel for the device with the given options in the context (the
// engine keeps one context per device and builds one program in it per maximum depth),
// reusing a cached binary when the source, options, device and driver are the same. The
// cache lives in $RAY_CACHE_DIR, else $XDG_CACHE_HOME/ray, else ~/.cache/ray; a cache that
// cannot be written is skipped silently. Throws DeviceError with the build log on failure.
// PoCL devices build one at a time; `firstRun`, when given, is called with the built program
// before the next may start: PoCL compiles (or takes from its cache) a kernel's work-group
// function at its first launch, and that too must not run on two PoCL devices at once.
KernelProgram buildKernelProgram(const OpenClDevice& device, const cl::Context& context, const std::string& options,
                                 const std::function<void(const cl::Program&)>& firstRun = {});

// Describes an OpenCL error code ("CL_OUT_OF_RESOURCES (-5)").
std::string openClErrorName(cl_int code);

}  // namespace ray
