#include "app/command_modules.h"

#include <chrono>
#include <iostream>
#include <thread>

#include "app/command_module_abi.h"
#include "app/render_command.h"
#include "core/module_loader.h"
#include "app/mpi_launch.h"

namespace ray {

namespace {

constexpr ModuleSpec kViewerModule{"libray_viewer.so", "RAY_VIEWER_MODULE", "ray's viewer module"};
// Global: Open MPI opens its components (mca_*.so) with dlopen, and before 3.0, or built with
// components that do not link its libraries, they look for libmpi's symbols in the global
// scope (open-mpi/ompi#3705; mpi4py reopens libmpi so). Debian 12's 4.1 works either way.
constexpr ModuleSpec kMpiModule{"libray_mpi.so", "RAY_MPI_MODULE", "ray's MPI module", true};

// How long a rank other than 0 waits before it repeats rank 0's message (reportOnOneRank).
constexpr auto kOtherRanksWait = std::chrono::seconds(2);

// The command's entry point in its module, or null with the reason in `failure`.
template <typename Entry>
Entry findEntryPoint(const ModuleSpec& spec, const char* name, std::string& failure) {
    LoadedModule module = loadModule(spec);
    Entry entry = nullptr;
    if (!resolveEntryPoint(module, name, entry)) failure = "ray: " + module.failure;
    return entry;
}

// A module that cannot be loaded under mpirun fails alike on every rank, before MPI starts.
// Rank 0 says why at once; the others wait first, and mpirun, which ends the job when a rank
// exits non-zero, ends them before they repeat it: one message. A rank that alone cannot
// load it (another host's install) still says so, after the wait.
int reportOnOneRank(const std::string& failure) {
    if (const int rank = launcherRank(); rank > 0) {
        std::this_thread::sleep_for(kOtherRanksWait);
        std::cerr << failure << " (on rank " << rank << ")\n";
    } else {
        std::cerr << failure << "\n";
    }
    return kExitRuntime;
}

}  // namespace

int runViewModule(const std::vector<std::string>& args) {
    std::string failure;
    const auto viewMain = findEntryPoint<RayViewMain>(kViewerModule, RAY_VIEW_MAIN, failure);
    if (!viewMain) {
        std::cerr << failure << "\n";
        return kExitRuntime;
    }
    std::vector<const char*> argv;
    for (const std::string& arg : args) argv.push_back(arg.c_str());
    argv.push_back(nullptr);
    return viewMain(int(args.size()), argv.data());
}

int runMpiModule(int argc, char** argv) {
    std::string failure;
    const auto mpiMain = findEntryPoint<RayMpiMain>(kMpiModule, RAY_MPI_MAIN, failure);
    return mpiMain ? mpiMain(argc, argv) : reportOnOneRank(failure);
}

}  // namespace ray
