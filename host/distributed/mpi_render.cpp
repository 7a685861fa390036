#include "distributed/mpi_render.h"

#include "app/command_module_abi.h"
#include "app/render_command.h"
#include "core/test_hooks.h"
#include "distributed/mpi_coordinator.h"
#include "distributed/mpi_protocol.h"
#include "distributed/mpi_startup.h"
#include "distributed/mpi_worker.h"

namespace ray {

int runDistributedCommand(int argc, char** argv, const std::vector<std::string>& args) {
    mpi::MpiSession session(argc, argv);
    mpi::Prepared prepared;
    const TestHooks& hooks = testHooks();
    try {
        if (session.rank != 0) {
            if (int code = mpi::startWorker(prepared, args, session.rank, hooks); code != 0) return code;
            if (prepared.nothingToRender) return 0;
            return mpi::runWorker(prepared, hooks);
        }
        std::vector<std::string> hosts;
        std::vector<int> silent;
        if (int code = mpi::startCoordinator(prepared, args, session, hosts, silent, hooks); code != 0) return code;
        if (prepared.nothingToRender) return 0;
        return mpi::runCoordinator(prepared, session, std::move(hosts), silent, hooks);
    } catch (...) {
        mpi::abortAll(session.rank, describeFailure(std::current_exception()).message);
    }
}

}  // namespace ray

// The module's entry point (app/command_module_abi.h).
extern "C" int ray_mpi_main(int argc, char** argv) {
    try {
        return ray::runDistributedCommand(argc, argv, std::vector<std::string>(argv + 1, argv + argc));
    } catch (...) {  // none crosses the C interface
        return ray::reportFailure(std::current_exception());
    }
}
