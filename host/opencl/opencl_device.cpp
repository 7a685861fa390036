#include "opencl/opencl_device.h"

#include <sched.h>
#include <sys/stat.h>

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <iostream>
#include <algorithm>
#include <filesystem>
#include <functional>
#include <iterator>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <optional>
#include <mutex>
#include <sstream>
#include <tuple>

#include "core/atomic_file.h"
#include "opencl/kernel_source.h"
#include "render/device_error.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

constexpr const char* kNoPlatformInstalled =
    "no OpenCL platform is installed (no ICD file in /etc/OpenCL/vendors or $OCL_ICD_VENDORS). Install one: PoCL "
    "for this CPU (Debian: apt-get install pocl-opencl-icd) or your GPU vendor's OpenCL driver; or render with the "
    "host reference renderer: --device ref";

constexpr const char* kPoclPlatformName = "Portable Computing Language";  // its CL_PLATFORM_NAME

// ICD files tell the loader which platforms are installed: $OCL_ICD_VENDORS (a folder or
// one file) when set, else /etc/OpenCL/vendors/*.icd.
struct IcdFile {
    std::string name;     // "pocl.icd"
    std::string library;  // what it names: "libpocl.so.2.10.0"
    bool isPocl() const { return library.find("pocl") != std::string::npos; }
};

std::vector<IcdFile> installedIcdFiles() {
    fs::path where = "/etc/OpenCL/vendors";
    if (const char* env = std::getenv("OCL_ICD_VENDORS"); env && *env) where = env;
    std::vector<fs::path> paths;
    std::error_code ec;
    if (fs::is_regular_file(where, ec)) {
        paths.push_back(where);
    } else {
        for (fs::directory_iterator it(where, ec), end; !ec && it != end; it.increment(ec))
            if (it->path().extension() == ".icd") paths.push_back(it->path());
    }
    std::sort(paths.begin(), paths.end());
    std::vector<IcdFile> files;
    for (const fs::path& path : paths) {
        IcdFile icd{path.filename().string(), {}};  // the library on its first line
        std::ifstream in(path);
        std::getline(in, icd.library);
        files.push_back(icd);
    }
    return files;
}

// What the platforms said when asked for their devices, for the messages.
struct PlatformReport {
    std::string name, vendor;
    size_t devices = 0;
    std::string failure;  // why it listed none
};

struct Enumeration {
    std::vector<OpenClDevice> devices;
    std::vector<PlatformReport> platforms;
    std::string loaderFailure;  // clGetPlatformIDs failed: no platform started
};

// Why there is no device, platform by platform, with the hint each one calls for. PoCL's
// cache hint only where PoCL is installed: it is PoCL that refuses to start without one.
std::string noDeviceMessage(const Enumeration& found) {
    std::vector<IcdFile> icds = installedIcdFiles();
    if (icds.empty()) return kNoPlatformInstalled;
    std::string installed;
    for (const IcdFile& icd : icds) installed += (installed.empty() ? "" : ", ") + icd.name;
    const bool poclInstalled = std::any_of(icds.begin(), icds.end(), [](const IcdFile& i) { return i.isPocl(); });
    const bool poclStarted = std::any_of(found.platforms.begin(), found.platforms.end(),
                                         [](const PlatformReport& p) { return p.name == kPoclPlatformName; });
    std::string message = "no OpenCL device found: ";
    if (found.platforms.empty()) {
        message += "OpenCL platforms are installed (" + installed + ") but none started" +
                   (found.loaderFailure.empty() ? std::string() : " (" + found.loaderFailure + ")");
    } else {
        message += "the platforms that started list none:";
        for (const PlatformReport& p : found.platforms) {
            message += " " + p.name + " (" + p.vendor + "): " + (p.failure.empty() ? "no device" : p.failure) + ";";
            if (p.name == "rusticl")
                message += " Mesa's rusticl lists only the drivers RUSTICL_ENABLE names (such as radeonsi; ray does "
                           "not use its llvmpipe unless chosen by index);";
        }
        message += " installed: " + installed;
    }
    message += ". ";
    if (poclInstalled)  // it started with no device, or not at all
        message += std::string(poclStarted ? "PoCL lists no device" : "PoCL is installed but did not start") +
                   ": it fails so when it cannot create its cache folder (set POCL_CACHE_DIR to a writable folder), "
                   "or when POCL_DEVICES names no device. ";
    else
        message += "For this CPU, install PoCL (Debian: apt-get install pocl-opencl-icd). ";
    return message + "Or render with the host reference renderer: --device ref";
}

std::string typeName(const OpenClDevice& d) {
    if (d.isGpu) return "GPU";
    if (d.isCpu) return "CPU";
    return "accelerator";
}

// 64-bit FNV-1a: names cache entries. Not cryptographic; a collision would at worst load
// a binary that then fails to build and is rebuilt from source.
uint64_t fnv1a(const std::string& text, uint64_t hash = 1469598103934665603ull) {
    for (unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
    return hash;
}

fs::path cacheDirectory() {
    if (const char* dir = std::getenv("RAY_CACHE_DIR"); dir && *dir) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "ray";
    if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "ray";
    return {};
}

// A folder of our own that this user can write, created if needed: `preferred`, else
// /tmp/ray-<uid>/<leaf> (0700, owned by us and not a link, so no other user can plant files
// in it). Empty when neither works.
fs::path writablePrivateFolder(const fs::path& preferred, const std::string& leaf) {
    std::error_code ec;
    if (!preferred.empty()) {
        fs::create_directories(preferred, ec);
        if (!ec && ::access(preferred.c_str(), W_OK | X_OK) == 0) return preferred;
    }
    fs::path base = fs::temp_directory_path(ec);
    if (ec) base = "/tmp";
    fs::path own = base / ("ray-" + std::to_string(::getuid()));
    ::mkdir(own.c_str(), 0700);
    struct stat st {};
    if (::lstat(own.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::getuid() || (st.st_mode & 077))
        return {};
    fs::path folder = own / leaf;
    fs::create_directories(folder, ec);
    return ec ? fs::path() : folder;
}

// PoCL keeps its compiled kernels under $POCL_CACHE_DIR, else $XDG_CACHE_HOME or ~/.cache,
// and refuses to start when it cannot create that folder (a user whose home is missing,
// e.g. nobody, in CI sandboxes). When the variable is unset it is pointed at a folder of
// ours before the first OpenCL call; the ICD loader starts PoCL in that call.
std::optional<fs::path> poclCacheFromEnvironment() {
    if (const char* set = std::getenv("POCL_CACHE_DIR"); set && *set) return fs::path(set);
    return std::nullopt;
}

// Our own folder for PoCL's cache: `pocl` in ray's cache folder (empty when there is none).
fs::path ourPoclCacheFolder() {
    fs::path ours = cacheDirectory();
    return ours.empty() ? ours : ours / "pocl";
}

// Whether this process may run on every online CPU, numbered 0..n-1 without a gap: then
// PoCL's worker thread i (one for each CPU it may use, at most n) can be pinned to CPU i.
// Pinned where the process is confined (taskset, a cgroup's cpuset), PoCL 3.1 would ask
// for a CPU outside its set, and it aborts when that fails.
bool mayRunOnEveryCpu() {
    const long online = ::sysconf(_SC_NPROCESSORS_ONLN);
    cpu_set_t allowed;
    if (online <= 0 || online > CPU_SETSIZE || ::sched_getaffinity(0, sizeof allowed, &allowed) != 0) return false;
    for (long cpu = 0; cpu < online; ++cpu)
        if (!CPU_ISSET(cpu, &allowed)) return false;
    return true;
}

// PoCL's CPU device runs its work-groups on a pool of worker threads, which Linux placed on
// one CPU at the start of a frame (both had last run there) and left there for 25 ms
// while the other CPU idled: a cache-hot thread is not moved to an idle CPU at once. So
// ray asks PoCL to pin worker i to CPU i (POCL_AFFINITY=1) where that is safe (above) and
// the variable is unset (docs/performance.md, "Keeping both cores busy", has the times).
// POCL_AFFINITY=0 leaves the threads to the scheduler; so does a POCL_MAX_PTHREAD_COUNT,
// which may ask for more threads than CPUs.
void preparePoclThreads() {
    if (std::getenv("POCL_AFFINITY") || std::getenv("POCL_MAX_PTHREAD_COUNT") || !mayRunOnEveryCpu()) return;
    ::setenv("POCL_AFFINITY", "1", 0);
}

// What PoCL reads from the environment as it starts, set before the first OpenCL call.
void preparePoclEnvironment() {
    static const bool done = [] {
        preparePoclThreads();
        if (poclCacheFromEnvironment()) return true;
        fs::path folder = writablePrivateFolder(ourPoclCacheFolder(), "pocl");
        if (!folder.empty()) ::setenv("POCL_CACHE_DIR", folder.c_str(), 0);
        return true;
    }();
    (void)done;
}

}  // namespace

void usePrivatePoclCacheFolder(const std::string& leaf) {
    const fs::path base = poclCacheFromEnvironment().value_or(ourPoclCacheFolder());
    fs::path folder = writablePrivateFolder(base.empty() ? base : base / leaf, "pocl-" + leaf);
    if (!folder.empty()) ::setenv("POCL_CACHE_DIR", folder.c_str(), 1);
}

namespace {

fs::path cacheFileFor(const OpenClDevice& device, const std::string& source, const std::string& options) {
    fs::path dir = cacheDirectory();
    if (dir.empty()) return {};
    std::string key = source + '\0' + options + '\0' + device.name + '\0' + device.driverVersion + '\0' +
                      device.platformName + '\0' + device.platformVersion;
    std::ostringstream name;
    name << "kernel-" << std::hex << std::setw(16) << std::setfill('0') << fnv1a(key) << ".bin";
    return dir / name.str();
}

std::vector<unsigned char> readFile(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return {};
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}

// The kernel cache is best effort: a binary that cannot be saved is compiled again next time.
void saveCachedBinary(const fs::path& file, const std::vector<unsigned char>& bytes) {
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    try {
        writeFileAtomically(file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    } catch (const FileWriteError&) {
    }
}

std::string buildLog(const cl::Program& program, const cl::Device& device) {
    try {
        return program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
    } catch (const cl::Error&) {
        return "(no build log)";
    }
}

// A program from a cached binary, or an empty optional when there is none or it fails.
bool tryCachedProgram(const cl::Context& context, const OpenClDevice& device, const fs::path& cacheFile,
                      const std::string& options, cl::Program& program) {
    if (cacheFile.empty()) return false;
    std::vector<unsigned char> binary = readFile(cacheFile);
    if (binary.empty()) return false;
    try {
        std::vector<cl_int> status;
        program = cl::Program(context, {device.device}, cl::Program::Binaries{binary}, &status);
        program.build({device.device}, options.c_str());
        return true;
    } catch (const cl::Error&) {
        return false;  // stale or foreign binary: rebuild from source
    }
}

}  // namespace

std::string OpenClDevice::description() const { return name + " (" + platformName + ")"; }

std::string openClErrorName(cl_int code) {
    switch (code) {
        case CL_DEVICE_NOT_FOUND: return "CL_DEVICE_NOT_FOUND (-1)";
        case CL_DEVICE_NOT_AVAILABLE: return "CL_DEVICE_NOT_AVAILABLE (-2)";
        case CL_MEM_OBJECT_ALLOCATION_FAILURE: return "CL_MEM_OBJECT_ALLOCATION_FAILURE (-4)";
        case CL_OUT_OF_RESOURCES: return "CL_OUT_OF_RESOURCES (-5)";
        case CL_OUT_OF_HOST_MEMORY: return "CL_OUT_OF_HOST_MEMORY (-6)";
        case CL_BUILD_PROGRAM_FAILURE: return "CL_BUILD_PROGRAM_FAILURE (-11)";
        case CL_INVALID_VALUE: return "CL_INVALID_VALUE (-30)";
        case CL_INVALID_BUFFER_SIZE: return "CL_INVALID_BUFFER_SIZE (-61)";
        case CL_INVALID_WORK_GROUP_SIZE: return "CL_INVALID_WORK_GROUP_SIZE (-54)";
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR (-1001)";
        default: return "OpenCL error " + std::to_string(code);
    }
}

namespace {

OpenClDevice describeDevice(const cl::Platform& platform, const cl::Device& device, int index) {
    OpenClDevice d;
    d.index = index;
    d.platform = platform;
    d.device = device;
    d.name = device.getInfo<CL_DEVICE_NAME>();
    d.platformName = platform.getInfo<CL_PLATFORM_NAME>();
    d.platformVersion = platform.getInfo<CL_PLATFORM_VERSION>();
    d.driverVersion = device.getInfo<CL_DRIVER_VERSION>();
    cl_device_type type = device.getInfo<CL_DEVICE_TYPE>();
    d.isGpu = (type & CL_DEVICE_TYPE_GPU) != 0;
    d.isCpu = (type & CL_DEVICE_TYPE_CPU) != 0;
    d.isPocl = d.platformName == kPoclPlatformName;
    d.isLlvmpipe = d.name.rfind("llvmpipe", 0) == 0;  // "llvmpipe (LLVM 15.0.6, 256 bits)"
    d.computeUnits = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
    d.nativeFloatWidth = device.getInfo<CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT>();
    d.globalMemory = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
    d.maxAllocation = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
    return d;
}

// Every device of every platform, platforms sorted (see enumerateOpenClDevices), and what
// each platform said.
Enumeration enumerateDevices() {
    preparePoclEnvironment();
    // One thread at a time: PoCL 3.1 lists no device to a second thread that asks while a
    // first one is starting it (startOpenClInBackground made that happen).
    static std::mutex oneAtATime;
    std::lock_guard lock(oneAtATime);
    Enumeration found;
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error& e) {
        // CL_PLATFORM_NOT_FOUND_KHR: no ICD file, or every platform failed to initialise.
        found.loaderFailure = std::string(e.what()) + " returned " + openClErrorName(e.err());
        return found;
    }
    struct Named {
        cl::Platform platform;
        PlatformReport report;
    };
    std::vector<Named> named;
    for (const cl::Platform& platform : platforms)
        named.push_back({platform, {platform.getInfo<CL_PLATFORM_NAME>(), platform.getInfo<CL_PLATFORM_VENDOR>(), 0, {}}});
    std::stable_sort(named.begin(), named.end(), [](const Named& a, const Named& b) {
        return std::tie(a.report.name, a.report.vendor) < std::tie(b.report.name, b.report.vendor);
    });
    for (Named& n : named) {
        std::vector<cl::Device> platformDevices;
        try {
            n.platform.getDevices(CL_DEVICE_TYPE_ALL, &platformDevices);
        } catch (const cl::Error& e) {
            n.report.failure = "clGetDeviceIDs returned " + openClErrorName(e.err());  // a platform with no device
        }
        n.report.devices = platformDevices.size();
        for (const cl::Device& device : platformDevices)
            found.devices.push_back(describeDevice(n.platform, device, int(found.devices.size())));
        found.platforms.push_back(n.report);
    }
    return found;
}

std::string listedDevices(const std::vector<OpenClDevice>& devices) {
    std::string list;
    for (const OpenClDevice& d : devices)
        list += (list.empty() ? "" : ", ") + std::to_string(d.index) + ": " + d.description() + " (" + typeName(d) + ")";
    return list;
}

// auto's order: a GPU, PoCL's CPU device, another CPU device, another device; llvmpipe never.
std::optional<int> autoRank(const OpenClDevice& d) {
    if (d.isLlvmpipe) return std::nullopt;
    if (d.isGpu) return 0;
    if (d.isCpu) return d.isPocl ? 1 : 2;
    return 3;
}

// The first device of the best rank, or nothing.
std::optional<OpenClDevice> bestRanked(const std::vector<OpenClDevice>& all,
                                       const std::function<std::optional<int>(const OpenClDevice&)>& rank) {
    std::optional<OpenClDevice> best;
    std::optional<int> bestRank;
    for (const OpenClDevice& d : all) {
        std::optional<int> r = rank(d);
        if (r && (!bestRank || *r < *bestRank)) best = d, bestRank = r;
    }
    return best;
}

DeviceError noSuchDevice(const std::string& what, const std::vector<OpenClDevice>& all, bool llvmpipeWouldDo) {
    std::string message = "no OpenCL " + what + " found; the devices are " + listedDevices(all) + ". ";
    for (const OpenClDevice& d : all)
        if (d.isLlvmpipe && llvmpipeWouldDo)
            message += "ray does not pick Mesa's llvmpipe (device " + std::to_string(d.index) +
                       ") by itself: it is 30-145x slower than PoCL and caps each work-item at 65,535 loop "
                       "iterations (heavy pixels come out wrong); choose it with --device " +
                       std::to_string(d.index) + " if you accept that. ";
    return DeviceError(message + "Or render with the host reference renderer: --device ref");
}

}  // namespace

std::vector<OpenClDevice> enumerateOpenClDevices() { return enumerateDevices().devices; }

std::vector<OpenClDevice> selectOpenClDevices(const std::string& selector) {
    Enumeration found = enumerateDevices();
    const std::vector<OpenClDevice>& all = found.devices;
    if (all.empty()) throw DeviceError(noDeviceMessage(found));
    if (selector == "all") {
        std::vector<OpenClDevice> chosen;
        std::copy_if(all.begin(), all.end(), std::back_inserter(chosen), [](const OpenClDevice& d) { return !d.isLlvmpipe; });
        if (chosen.empty()) throw noSuchDevice("device but llvmpipe", all, true);
        return chosen;
    }
    if (selector == "gpu" || selector == "cpu" || selector == "auto") {
        const bool gpu = selector == "gpu", cpu = selector == "cpu";
        std::optional<OpenClDevice> best = bestRanked(all, [&](const OpenClDevice& d) -> std::optional<int> {
            std::optional<int> rank = autoRank(d);
            if ((gpu && !d.isGpu) || (cpu && !d.isCpu)) return std::nullopt;
            return rank;
        });
        if (!best) throw noSuchDevice(gpu ? "GPU device" : cpu ? "CPU device but llvmpipe" : "device but llvmpipe", all, !gpu);
        return {*best};
    }
    // An index or a comma-separated list of them ("0,2"), each device once.
    std::vector<OpenClDevice> chosen;
    std::stringstream list(selector);
    for (std::string item; std::getline(list, item, ',');) {
        char* end = nullptr;
        long index = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || index < 0 || index >= long(all.size()))
            throw DeviceError("there is no OpenCL device " + item + "; ray --list-devices shows " +
                              std::to_string(all.size()) + " (0 to " + std::to_string(all.size() - 1) + ")");
        bool seen = false;
        for (const OpenClDevice& d : chosen) seen = seen || d.index == int(index);
        if (!seen) chosen.push_back(all[size_t(index)]);
    }
    if (chosen.empty()) throw DeviceError("--device " + selector + " names no device; see ray --list-devices");
    return chosen;
}

std::string llvmpipeWarning(const OpenClDevice& device) {
    if (!device.isLlvmpipe) return {};
    return "device " + std::to_string(device.index) + " (" + device.description() +
           ") is Mesa's llvmpipe: it stops each work-item after 65,535 loop iterations in all, silently, so heavy "
           "pixels (many samples, deep reflections, big scenes) can come out wrong; it is also 30-145x slower than "
           "PoCL (--device cpu)";
}

std::jthread startOpenClInBackground() {
    preparePoclEnvironment();  // here: it may set an environment variable, which no thread may do
    return std::jthread([] {
        try {
            enumerateDevices();
        } catch (...) {
            // The same calls fail again where the render makes them, and say so there.
        }
    });
}

void printOpenClDevices(std::ostream& out) {
    Enumeration found = enumerateDevices();
    const std::vector<OpenClDevice>& devices = found.devices;
    if (devices.empty()) {
        out << noDeviceMessage(found) << "\n";
        return;
    }
    for (const OpenClDevice& d : devices) {
        out << d.index << ": " << d.name << "\n"
            << "   platform " << d.platformName << " (" << d.platformVersion << "), driver " << d.driverVersion
            << "\n"
            << "   " << typeName(d) << ", " << d.computeUnits << " compute units, "
            << d.globalMemory / (1024 * 1024) << " MiB global memory, " << d.maxAllocation / (1024 * 1024)
            << " MiB largest buffer\n";
        if (d.isLlvmpipe)
            out << "   Mesa's llvmpipe: never picked by auto, cpu or all (it caps each work-item at 65,535 loop "
                   "iterations); only by its index\n";
    }
    out << "ref: the host reference renderer (always available)\n";
}

namespace {
std::mutex poclCompiler;  // poclCompilerLock's
}  // namespace

std::unique_lock<std::mutex> poclCompilerLock(const OpenClDevice& device, bool wait) {
    if (!device.isPocl) return {};
    return wait ? std::unique_lock(poclCompiler) : std::unique_lock(poclCompiler, std::try_to_lock);
}

int endWithoutPoclBuilds(int exitCode) {
    if (poclCompiler.try_lock()) return exitCode;  // kept to the end: no build starts now
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    std::_Exit(exitCode);
}

KernelProgram buildKernelProgram(const OpenClDevice& device, const cl::Context& context, const std::string& options,
                                 const std::function<void(const cl::Program&)>& firstRun) {
    auto start = std::chrono::steady_clock::now();
    // PoCL devices of one process build one at a time: two PoCL devices compiling the
    // packet kernel at once under load ended once in three suite runs with "LLVM ERROR: out
    // of memory" (POCL_DEVICES="pthread pthread", --device all; never alone). The second
    // then finds the first's binary in the cache instead of compiling it again. The first
    // launch (firstRun), where PoCL compiles the work-group function with LLVM, is made
    // under the same lock. (The same message came back with the builds one at a time: a
    // build still running as the process ended or another device's program was freed,
    // which endWithoutPoclBuilds and DeviceSlot's destructor now prevent.)
    const std::unique_lock oneAtATime = poclCompilerLock(device);
    KernelProgram result;
    result.context = context;
    const std::string source = kernelProgramSource();
    const fs::path cacheFile = cacheFileFor(device, source, options);

    result.fromCache = tryCachedProgram(result.context, device, cacheFile, options, result.program);
    if (!result.fromCache) {
        result.program = cl::Program(result.context, source);
        try {
            result.program.build({device.device}, options.c_str());
        } catch (const cl::Error& e) {
            throw DeviceError("the OpenCL kernel failed to build for " + device.description() + " (" +
                              openClErrorName(e.err()) + "). Build log:\n" + buildLog(result.program, device.device) +
                              "\nTry another device (ray --list-devices) or --device ref (the host reference renderer).");
        }
        if (!cacheFile.empty()) {
            try {
                auto binaries = result.program.getInfo<CL_PROGRAM_BINARIES>();
                if (!binaries.empty() && !binaries.front().empty()) saveCachedBinary(cacheFile, binaries.front());
            } catch (const cl::Error&) {
                // Caching is an optimization; a device that cannot hand out binaries is fine.
            }
        }
    }
    if (firstRun) firstRun(result.program);
    result.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace ray
