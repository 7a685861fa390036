#include "distributed/mpi_startup.h"

#include <mpi.h>

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <thread>

#include "app/render_command.h"
#include "core/steady_clock.h"
#include "distributed/mpi_protocol.h"
#include "distributed/mpi_worker.h"
#include "render/tile_scheduler.h"
#include "render/tile_side.h"

namespace ray::mpi {

namespace {

// Open MPI binds each rank to one core by default (for -n 1 and 2), which suits one rank
// per core; ray's ranks render on every core their OpenCL CPU device sees. A rank alone on
// its machine gets every core back (bound, it renders as on one core: user-guide.md,
// "Across machines"). Several ranks on one machine keep the binding they were given: they
// share the cores. Before the first OpenCL call, whose threads inherit the mask.
void unbindLoneRank() {
    const char* localRanks = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    if (!localRanks || std::atoi(localRanks) != 1) return;
    cpu_set_t every;
    CPU_ZERO(&every);
    const long cores = sysconf(_SC_NPROCESSORS_ONLN);
    for (long c = 0; c < cores && c < CPU_SETSIZE; ++c) CPU_SET(int(c), &every);
    sched_setaffinity(0, sizeof every, &every);  // best effort: a refusal leaves the binding
}

// Every rank must render the same frame: a hash of the command line and the scene file's
// bytes, compared with rank 0's (a host of a hostfile with another copy of the scene
// would otherwise paint its tiles from another scene).
uint64_t fingerprintOf(const std::vector<std::string>& args, const std::filesystem::path& scene) {
    std::string text;
    for (const std::string& a : args) text += a + '\0';
    std::ifstream in(scene, std::ios::binary);
    text.append(std::istreambuf_iterator<char>(in), {});
    return std::max<uint64_t>(1, std::hash<std::string>{}(text));
}

// What a rank's main thread does before its start-up (prepare), which a worker runs on
// another thread: setenv, which no thread may call while another runs, and the binding of
// this thread, which the threads it starts inherit (sched_setaffinity binds the caller),
// both before the first OpenCL call. Ranks on one machine must not compile into one PoCL
// cache at once.
void beforeOpenCl(int rank) {
    usePrivatePoclCacheFolder("rank-" + std::to_string(rank));
    unbindLoneRank();
}

Failure prepare(Prepared& p, const std::vector<std::string>& args, int rank) {
    try {
        if (!args.empty() && (args.front() == "view" || args.front() == "explain"))
            throw UsageError("ray " + args.front() + " runs in one process; start it without mpirun");
        p.options = parseCommandLine(args);
        const CliOptions& o = p.options;
        if (o.help || o.version || o.listDevices) {
            p.nothingToRender = true;
            if (rank == 0 && o.help) std::cout << kUsageText;
            if (rank == 0 && o.version) std::cout << "ray " << RAY_VERSION << "\n";
            if (rank == 0 && o.listDevices) printOpenClDevices(std::cout);
            return {};
        }
        if (isReferenceDevice(o.device))
            throw UsageError("--device ref renders on the host in one process; run it without mpirun, or choose "
                             "OpenCL devices (--device cpu, gpu, all)");
        installInterruptHandlers();
        if (rank == 0) p.output = checkOutputs(o);
        CliOptions loadOptions = o;
        loadOptions.quiet = o.quiet || rank != 0;  // the scene's warnings once, from rank 0
        auto start = Clock::now();
        p.scene = std::make_shared<const Scene>(loadSceneFor(loadOptions));
        p.loadSeconds = secondsSince(start);
        p.fingerprint = fingerprintOf(args, o.scene);
        checkImageFitsInMemory(o);
        p.devices = selectOpenClDevices(o.device);
    } catch (...) {
        return describeFailure(std::current_exception());
    }
    return {};
}

std::string processorName() {
    char name[MPI_MAX_PROCESSOR_NAME] = {};
    int length = 0;
    MPI_Get_processor_name(name, &length);
    return std::string(name, strnlen(name, MPI_MAX_PROCESSOR_NAME));
}

}  // namespace

MpiSession::MpiSession(int argc, char** argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

int startWorker(Prepared& p, const std::vector<std::string>& args, int rank, const TestHooks& hooks) {
    Failure started;
    std::atomic<bool> ready{false};
    beforeOpenCl(rank);
    std::thread preparing([&] {
        started = prepare(p, args, rank);
        if (hooks.stopWhileLoadingSeconds > 0) {
            std::this_thread::sleep_for(std::chrono::duration<double>(hooks.stopWhileLoadingSeconds));
            stopThisRank();  // the whole process, this thread's heartbeats included
        }
        ready = true;
    });
    Clock::time_point lastSent{};
    while (!ready) {
        if (secondsSince(lastSent) >= kHeartbeatSeconds) {
            sendHeartbeat();
            lastSent = Clock::now();
        }
        if (interrupted()) leaveInterrupted();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    preparing.join();
    const Json hello = {{"code", started.exitCode},
                        {"message", started.message},
                        {"fingerprint", p.fingerprint},
                        {"host", processorName()}};
    sendText(hello.dump(), 0, kHello);
    return awaitDecision(kStart);
}

int startCoordinator(Prepared& p, const std::vector<std::string>& args, const MpiSession& mpi,
                     std::vector<std::string>& hosts, std::vector<int>& silent, const TestHooks& hooks) {
    beforeOpenCl(0);
    const Failure mine = prepare(p, args, 0);
    hosts.assign(size_t(mpi.size), "");
    hosts[0] = processorName();
    // Workers still loading beat meanwhile; their heartbeats queued during rank 0's own
    // start-up count from when they are read.
    const double limit = p.options.rankTimeout > 0 ? p.options.rankTimeout : TileScheduler::kDeadlineFloorSeconds;
    std::vector<std::optional<Json>> hellos(size_t(mpi.size));
    std::vector<Clock::time_point> lastHeard(size_t(mpi.size), Clock::now());
    std::vector<bool> gone(size_t(mpi.size), false);
    auto pending = [&] {
        for (int r = 1; r < mpi.size; ++r)
            if (!hellos[size_t(r)] && !gone[size_t(r)]) return true;
        return false;
    };
    while (pending()) {
        if (interrupted()) leaveInterrupted();
        int flag = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
        if (flag) {
            const int from = status.MPI_SOURCE;
            lastHeard[size_t(from)] = Clock::now();
            if (status.MPI_TAG == kAlive) {
                MPI_Recv(nullptr, 0, MPI_INT, from, kAlive, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            } else if (status.MPI_TAG == kHello) {
                try {
                    hellos[size_t(from)] = Json::parse(receiveText(from, kHello));
                    hosts[size_t(from)] = hellos[size_t(from)]->at("host").get<std::string>();
                } catch (const Json::exception& e) {
                    abortAll(0, "an unreadable start-up message from rank " + std::to_string(from) + ": " + e.what());
                }
            } else {
                abortAll(0, "unexpected message (tag " + std::to_string(status.MPI_TAG) + ") from rank " +
                                std::to_string(from) + " in the start-up");
            }
            continue;
        }
        for (int r = 1; r < mpi.size; ++r) {
            const double silence = secondsSince(lastHeard[size_t(r)]);
            if (hellos[size_t(r)] || gone[size_t(r)] || silence <= limit) continue;
            gone[size_t(r)] = true;
            silent.push_back(r);
            std::cerr << "ray: warning: rank " << r << " does not answer: it sent nothing for " << formatSeconds(silence)
                      << " in its start-up, not even a heartbeat (its deadline: " << formatSeconds(limit)
                      << "); the others render the frame without it (--rank-timeout sets the deadline)\n"
                      << std::flush;
        }
        idle();
    }

    // The first rank that failed, in rank order: its own failure, else a scene that differs.
    int code = mine.exitCode;
    if (code != 0) std::cerr << mine.message << "\n";
    for (int r = 1; r < mpi.size && code == 0; ++r) {
        if (!hellos[size_t(r)]) continue;
        const Json& hello = *hellos[size_t(r)];
        int theirs = hello.value("code", int(kExitRuntime));
        std::string message = hello.value("message", std::string());
        if (theirs == 0 && hello.value("fingerprint", uint64_t(0)) != p.fingerprint) {
            theirs = kExitBadInput;
            message = "ray: the command line or the scene file of rank " + std::to_string(r) +
                      " differs from rank 0's; every rank must render the same scene (the same file at the same "
                      "path on every host, e.g. a shared folder)";
        }
        if (theirs != 0) {
            code = theirs;
            std::cerr << message << "\n(on rank " << r << ")\n";
        }
    }
    // To the silent ranks too (a small message, sent without their receiving it): one that
    // resumes then renders as a dropped rank, which gets no tile, and ends with the job.
    // Measured: while rank 0 sent nothing to a rank stopped in its start-up, Open MPI
    // 4.1.4's mpirun hung or crashed after rank 0's MPI_Abort in 5 of 28 runs; since, none.
    const bool byAbort = !silent.empty() && (code != 0 || p.nothingToRender);
    for (int r = 1; r < mpi.size; ++r) sendDecision({code, byAbort}, r, kStart);
    if (byAbort) endJobWithout(silent, code, hosts, false, hooks.abortAfterSeconds);
    return code;
}

int tileSideOf(const Prepared& p) {
    return frameTileSide(p.options.settings, *p.scene, /*cancellable=*/true, p.options.tileSize);
}

FrameRequest frameRequest(const Prepared& p, TileSource& tiles, std::function<void(const FinishedTile&)> onTile) {
    FrameRequest request;
    request.tileSize = tileSideOf(p);
    request.tiles = &tiles;
    request.onTile = std::move(onTile);
    request.cancel = interruptFlag();
    return request;
}

RenderStats renderShare(OpenClFrameSource& frames, const Prepared& p, const FrameRequest& request) {
    return frames.render(p.scene, p.scene->camera, p.options.settings, request).stats;
}

}  // namespace ray::mpi
