#include "distributed/mpi_render.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <functional>
#include <iterator>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sched.h>
#include <stdexcept>
#include <string>
#include <thread>
#include <unistd.h>

#include "app/cli.h"
#include "app/command_module_abi.h"
#include "app/progress.h"
#include "app/render_command.h"
#include "core/test_hooks.h"
#include "opencl/opencl_device.h"
#include "opencl/opencl_frame_source.h"
#include "render/tile_scheduler.h"
#include "render/tile_side.h"

namespace ray {

namespace {

using Clock = std::chrono::steady_clock;
using Json = nlohmann::json;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The messages of a distributed frame, by tag. W is a worker rank (1..N-1), 0 rank 0.
enum Tag : int {
    kRequest = 1,  // W -> 0: int, how many more tiles W's devices wait for
    kTiles,        // 0 -> W: 4 ints (x, y, width, height) a tile; fewer tiles than asked: no more
    kResult,       // W -> 0: a TileResultHeader, then width x height x 3 floats (linear RGB)
    kFinished,     // W -> 0: JSON, W's statistics (and why its devices failed, if they did)
    kEnd,          // 0 -> W: a Decision, the exit code: the frame is over
    kAlive,        // W -> 0: empty, a heartbeat: W's message loop runs (kHeartbeatSeconds)
    kHello,        // W -> 0: JSON, W's start-up done: its outcome, fingerprint and host
    kStart,        // 0 -> W: a Decision, 0: render; else the exit code every rank ends with
};

// Rank 0's word to a worker on how the job goes on (kStart) or ends (kEnd).
struct Decision {
    int code = 0;        // kStart: 0 to render, else the exit code; kEnd: the exit code
    int byAbort = 0;     // 1: rank 0 ends the job with MPI_Abort, a rank having stopped answering
};
static_assert(sizeof(Decision) == 2 * sizeof(int), "a Decision is sent as two MPI_INTs");

// A worker that has sent nothing for this long sends a heartbeat, from its message loop,
// which never waits on the engine: it goes on while the rank's kernel compiles or a long
// tile renders. Rank 0 can so tell a rank that is slow (it answers) from one that is
// stopped or wedged (silent for the usual deadline, 10 s or more: dropped, whatever it was
// doing), instead of waiting for a first result for kFirstTileSeconds (120 s).
constexpr double kHeartbeatSeconds = 1;

struct TileResultHeader {
    int32_t x, y, width, height, device, reserved;
    uint64_t primaryRays, shadowRays, secondaryRays;
};
static_assert(sizeof(TileResultHeader) == 48, "the result header is sent as bytes between hosts of one kind");

// A polling loop's pause when nothing happened: blocking MPI calls spin a core, which
// would halve a 2-core rank's render; 0.2 ms adds little to a tile of tens of milliseconds.
void idle() { std::this_thread::sleep_for(std::chrono::microseconds(200)); }

bool interrupted() { return interruptFlag()->load(); }

// Ends every rank: an error that leaves the frame's state unknown.
[[noreturn]] void abortAll(int rank, const std::string& message) {
    std::cerr << "ray: rank " << rank << ": " << message << "\n" << std::flush;
    MPI_Abort(MPI_COMM_WORLD, kExitRuntime);
    std::_Exit(kExitRuntime);
}

// How long a worker waits for mpirun to end it after rank 0's MPI_Abort (awaitAbort).
constexpr double kAwaitAbortSeconds = 60;

// After SIGINT/SIGTERM (mpirun forwards Ctrl-C as SIGTERM to every rank and kills those
// left after a few seconds): leave at once, without MPI_Finalize, which waits for ranks
// that may be gone.
[[noreturn]] void leaveInterrupted() {
    std::cerr << std::flush;
    std::_Exit(interruptExitCode());
}

// Rank 0 ends the job with MPI_Abort, a rank having stopped answering: this worker waits
// for mpirun to end it (SIGTERM: leaveInterrupted) instead of calling MPI_Finalize, which
// waits for every rank, the stopped one too. Measured with Open MPI 4.1.4
// (bench/mpi_abort_race.sh: 3 ranks, the third stopped, rank 0 aborting a second later):
// with the second rank in MPI_Finalize, mpirun hung (every rank a zombie) or crashed in 9
// of 25 runs; with it waiting so, in none of 25. Should mpirun never come, the worker
// leaves without MPI_Finalize (mpirun then ends the job for a rank gone unannounced).
[[noreturn]] void awaitAbort(int code) {
    const auto start = Clock::now();
    while (secondsSince(start) < kAwaitAbortSeconds) {
        if (interrupted()) leaveInterrupted();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::_Exit(code);
}

// A worker waits for rank 0's decision (`tag`: kStart or kEnd) and returns its exit code;
// it never returns when the job ends by MPI_Abort (awaitAbort).
int awaitDecision(Tag tag) {
    while (true) {
        int flag = 0;
        MPI_Iprobe(0, tag, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
        if (flag) {
            Decision decision;
            MPI_Recv(&decision, 2, MPI_INT, 0, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (decision.byAbort) awaitAbort(decision.code);
            return decision.code;
        }
        if (interrupted()) leaveInterrupted();
        idle();
    }
}

void sendDecision(const Decision& decision, int rank, Tag tag) {
    MPI_Send(&decision, 2, MPI_INT, rank, tag, MPI_COMM_WORLD);
}

// Open MPI binds each rank to one core by default (for -n 1 and 2), which suits one rank
// per core; ray's ranks render on every core their OpenCL CPU device sees. A rank alone on
// its machine gets every core back (measured: chess.xml 1024x768 under mpirun -n 1, 1.45 s
// bound against 0.87 s unbound, as in one process). Several ranks on one machine keep the
// binding they were given: they share the cores. Before the first OpenCL call, whose
// threads inherit the mask.
void unbindLoneRank() {
    const char* localRanks = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    if (!localRanks || std::atoi(localRanks) != 1) return;
    cpu_set_t every;
    CPU_ZERO(&every);
    const long cores = sysconf(_SC_NPROCESSORS_ONLN);
    for (long c = 0; c < cores && c < CPU_SETSIZE; ++c) CPU_SET(int(c), &every);
    sched_setaffinity(0, sizeof every, &every);  // best effort: a refusal leaves the binding
}

struct MpiSession {
    int rank = 0, size = 1;
    MpiSession(int argc, char** argv) {
        int provided = 0;
        MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        MPI_Comm_size(MPI_COMM_WORLD, &size);
    }
    ~MpiSession() { MPI_Finalize(); }
};

// What every rank holds once the command line and the scene are loaded.
struct Prepared {
    CliOptions options;
    std::filesystem::path output;  // rank 0
    std::shared_ptr<const Scene> scene;  // shared with each frame source that renders it
    std::vector<OpenClDevice> devices;
    double loadSeconds = 0;
    bool nothingToRender = false;  // --help, --version, --list-devices
    uint64_t fingerprint = 0;      // of the command line and the scene file; 0 until loaded
};

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

void sendText(const std::string& text, int to, int tag) {
    MPI_Send(text.data(), int(text.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD);
}

std::string receiveText(int from, int tag, MPI_Status* status = nullptr) {
    MPI_Status probed;
    MPI_Probe(from, tag, MPI_COMM_WORLD, &probed);
    int length = 0;
    MPI_Get_count(&probed, MPI_CHAR, &length);
    std::string text(size_t(length), '\0');
    MPI_Recv(text.data(), length, MPI_CHAR, probed.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (status) *status = probed;
    return text;
}

// The side of the frame's tiles: rank 0 cuts the image by it, every rank's devices check
// their limits with it. Every rank computes the same from the same command line and scene.
int tileSideOf(const Prepared& p) {
    return frameTileSide(p.options.settings, *p.scene, /*cancellable=*/true, p.options.tileSize);
}

// A rank's frame (render/frame_source.h): the tiles admitted from `tiles`, each finished one
// to `onTile`; the image the source assembles is not used (rank 0 pastes the kept tiles).
FrameRequest frameRequest(const Prepared& p, TileSource& tiles, std::function<void(const FinishedTile&)> onTile) {
    FrameRequest request;
    request.tileSize = tileSideOf(p);
    request.tiles = &tiles;
    request.onTile = std::move(onTile);
    request.cancel = interruptFlag();
    return request;
}

// One frame of the rank's share on its own devices.
RenderStats renderShare(OpenClFrameSource& frames, const Prepared& p, const FrameRequest& request) {
    return frames.render(p.scene, p.scene->camera, p.options.settings, request).stats;
}

// A rank's statistics as rank 0 merges them: its devices' shares and set-up times.
Json statsToMessage(const RenderStats& frame, double loadSeconds, const std::string& failure) {
    Json devices = Json::array();
    for (const DeviceStats& d : frame.devices)
        devices.push_back({{"device", d.device}, {"tiles", d.tiles}, {"pixels", d.pixels}, {"rays", d.rays},
                           {"busy", d.busySeconds}, {"failed", d.failed}, {"failure", d.failure}});
    // The rays are counted by rank 0 from the tiles it keeps (TileResultHeader).
    return {{"devices", devices},
            {"load", loadSeconds},
            {"bvh", frame.bvhBuildSeconds},
            {"kernel_build", frame.kernelBuildSeconds},
            {"upload", frame.uploadSeconds},
            {"warnings", frame.warnings},
            {"failure", failure}};
}

void mergeRankStats(RenderStats& stats, int rank, const Json& m) {
    for (const Json& d : m.at("devices")) {
        DeviceStats device;
        device.device = d.at("device").get<std::string>();
        device.tiles = d.at("tiles").get<int>();
        device.pixels = d.at("pixels").get<uint64_t>();
        device.rays = d.at("rays").get<uint64_t>();
        device.busySeconds = d.at("busy").get<double>();
        device.failed = d.at("failed").get<bool>();
        device.failure = d.at("failure").get<std::string>();
        stats.devices.push_back(device);
        stats.deviceRanks.push_back(rank);
    }
    stats.bvhBuildSeconds = std::max(stats.bvhBuildSeconds, m.at("bvh").get<double>());
    stats.kernelBuildSeconds = std::max(stats.kernelBuildSeconds, m.at("kernel_build").get<double>());
    stats.uploadSeconds = std::max(stats.uploadSeconds, m.at("upload").get<double>());
    for (const Json& w : m.at("warnings")) stats.warnings.push_back("rank " + std::to_string(rank) + ": " + w.get<std::string>());
}

// ---------------------------------------------------------------------------------------
// A worker rank (1..N-1).

// The device threads' tile source on a worker: each next() waits for the main thread to
// bring a tile from rank 0.
class RemoteTiles : public TileSource {
public:
    bool next(TileRect& tile) override {
        std::unique_lock lock(mutex_);
        ++waiting_;
        while (ready_.empty() && !exhausted_ && !interrupted()) arrived_.wait_for(lock, std::chrono::milliseconds(50));
        --waiting_;
        if (ready_.empty()) return false;
        tile = ready_.front();
        ready_.pop_front();
        return true;
    }
    // How many more tiles to ask rank 0 for, `asked` being already on their way.
    int shortfall(int asked) {
        std::lock_guard lock(mutex_);
        return exhausted_ ? 0 : waiting_ - int(ready_.size()) - asked;
    }
    void arrive(const std::vector<TileRect>& tiles, bool noMore) {
        std::lock_guard lock(mutex_);
        ready_.insert(ready_.end(), tiles.begin(), tiles.end());
        exhausted_ = exhausted_ || noMore;
        arrived_.notify_all();
    }

private:
    std::mutex mutex_;
    std::condition_variable arrived_;
    std::deque<TileRect> ready_;
    int waiting_ = 0;
    bool exhausted_ = false;
};

// Finished tiles waiting for the main thread to send them, as ready-made messages.
class Outbox {
public:
    void push(const FinishedTile& tile) {
        std::vector<char> message(sizeof(TileResultHeader) + tile.rect.pixels() * 3 * sizeof(float));
        TileResultHeader header{tile.rect.x, tile.rect.y, tile.rect.width, tile.rect.height, tile.device, 0,
                                tile.primaryRays, tile.shadowRays, tile.secondaryRays};
        std::memcpy(message.data(), &header, sizeof header);
        std::memcpy(message.data() + sizeof header, tile.rgb, tile.rect.pixels() * 3 * sizeof(float));
        std::lock_guard lock(mutex_);
        messages_.push_back(std::move(message));
    }
    std::optional<std::vector<char>> pop() {
        std::lock_guard lock(mutex_);
        if (messages_.empty()) return std::nullopt;
        std::vector<char> message = std::move(messages_.front());
        messages_.pop_front();
        return message;
    }

private:
    std::mutex mutex_;
    std::deque<std::vector<char>> messages_;
};

std::vector<TileRect> receiveTiles(int& count) {
    MPI_Status status;
    MPI_Probe(0, kTiles, MPI_COMM_WORLD, &status);
    int ints = 0;
    MPI_Get_count(&status, MPI_INT, &ints);
    std::vector<int> values(size_t(std::max(ints, 0)));
    MPI_Recv(values.data(), ints, MPI_INT, 0, kTiles, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    std::vector<TileRect> tiles;
    for (size_t i = 0; i + 3 < values.size(); i += 4) tiles.push_back({values[i], values[i + 1], values[i + 2], values[i + 3]});
    count = int(tiles.size());
    return tiles;
}

// The test hooks that make a worker stop itself (core/test_hooks.h; tests/mpi.sh) do it
// with SIGSTOP, as a wedged host stops answering without dying, and say when on stderr:
// in its start-up (stopWhileLoadingSeconds: its main thread beating meanwhile, before it
// tells rank 0 how the start-up went), once it has sent some tiles (a rank hung mid-frame),
// or some seconds into its message loop (with slowBuild, a rank stopped while it compiles).
void stopThisRank() {
    // The moment, for the test to time rank 0 from (Unix time, seconds).
    const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    std::fprintf(stderr, "ray: test hook: this rank stops itself (SIGSTOP) at %.3f\n", now);
    std::fflush(stderr);
    raise(SIGSTOP);
}

class StopHook {
public:
    explicit StopHook(const TestHooks& hooks)
        : start_(Clock::now()), after_(hooks.stopAfterTiles), afterSeconds_(hooks.stopAfterSeconds) {}
    void tileSent() {
        if (after_ > 0 && ++sent_ == after_) stopThisRank();
    }
    void tick() {
        if (afterSeconds_ > 0 && secondsSince(start_) >= afterSeconds_) {
            afterSeconds_ = 0;
            stopThisRank();
        }
    }

private:
    Clock::time_point start_;
    int after_ = 0, sent_ = 0;
    double afterSeconds_ = 0;
};

int runWorker(Prepared& p, const TestHooks& hooks) {
    StopHook stopHook(hooks);
    RemoteTiles tiles;
    Outbox outbox;
    std::atomic<bool> rendered{false};
    RenderStats frameStats;
    std::string failure;
    beginRendering();
    std::thread render([&] {
        try {
            OpenClFrameSource frames(p.devices);
            frameStats = renderShare(frames, p, frameRequest(p, tiles, [&](const FinishedTile& tile) { outbox.push(tile); }));
        } catch (...) {
            // Every device of this rank failed: rank 0 gives its tiles to the others.
            failure = describeFailure(std::current_exception()).message;
        }
        rendered = true;
    });

    std::deque<int> requests;  // tiles asked for, by request, answers pending
    int asked = 0;
    bool finished = false;
    Clock::time_point lastSent{};  // never: the first heartbeat goes at once
    while (!finished) {
        bool active = false;
        if (int more = tiles.shortfall(asked); more > 0) {
            MPI_Send(&more, 1, MPI_INT, 0, kRequest, MPI_COMM_WORLD);
            lastSent = Clock::now();
            requests.push_back(more);
            asked += more;
            active = true;
        }
        while (auto message = outbox.pop()) {
            MPI_Send(message->data(), int(message->size()), MPI_BYTE, 0, kResult, MPI_COMM_WORLD);
            lastSent = Clock::now();
            stopHook.tileSent();
            active = true;
        }
        // Any message tells rank 0 this rank is alive; a heartbeat only after a second
        // without one (the engine may be compiling, or rendering a long tile).
        if (secondsSince(lastSent) >= kHeartbeatSeconds) {
            MPI_Send(nullptr, 0, MPI_INT, 0, kAlive, MPI_COMM_WORLD);
            lastSent = Clock::now();
        }
        stopHook.tick();
        int flag = 0;
        MPI_Iprobe(0, kTiles, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
        if (flag && !requests.empty()) {
            int count = 0;
            std::vector<TileRect> answer = receiveTiles(count);
            const int wanted = requests.front();
            requests.pop_front();
            asked -= wanted;
            tiles.arrive(answer, count < wanted);
            active = true;
        }
        // The engine has returned and every tile it kept is sent: report, once the
        // answers still on their way are in (they would be no tile or a spare one).
        if (rendered && requests.empty()) {
            render.join();
            while (auto message = outbox.pop())
                MPI_Send(message->data(), int(message->size()), MPI_BYTE, 0, kResult, MPI_COMM_WORLD);
            if (interrupted()) leaveInterrupted();
            sendText(statsToMessage(frameStats, p.loadSeconds, failure).dump(), 0, kFinished);
            finished = true;
        }
        if (!active) idle();
    }
    return awaitDecision(kEnd);
}

// ---------------------------------------------------------------------------------------
// Rank 0: hands the tiles out, renders some, assembles the image.

// Rank 0's ranks and the image their tiles make: the frame's tile scheduler, whose
// workers are the ranks, and the image each tile is pasted into as it is kept.
class RankTiles {
public:
    RankTiles(int width, int height, int side) : scheduler(TileGrid(width, height, side)), image_(width, height) {}

    // A finished tile from `rank`: kept (true) unless another rank delivered it first.
    // Throws std::invalid_argument for a rectangle that is no tile of the frame or a pixel
    // count that does not match it (a protocol error).
    bool deliver(int rank, const TileRect& rect, const float* rgb, size_t floatCount) {
        const std::optional<int> index = scheduler.indexOf(rect);
        if (!index)
            throw std::invalid_argument("rank " + std::to_string(rank) + " delivered a tile at (" +
                                        std::to_string(rect.x) + ", " + std::to_string(rect.y) +
                                        ") that is not one of the frame's");
        if (floatCount != rect.pixels() * 3)
            throw std::invalid_argument("rank " + std::to_string(rank) + " delivered a tile with " +
                                        std::to_string(floatCount) + " values for " + std::to_string(rect.pixels()) +
                                        " pixels");
        return scheduler.deliver(rank, *index, [&] { pasteTile(image_, rect, rgb); });
    }
    std::vector<TileRect> handOut(int rank, int count) {
        std::vector<TileRect> tiles;
        for (int index : scheduler.handOut(rank, count)) tiles.push_back(scheduler.tile(index));
        return tiles;
    }
    // The finished image (call once complete(); unrendered tiles are black).
    Image takeImage() { return std::move(image_); }

    TileScheduler scheduler;

private:
    Image image_;  // written under the scheduler's lock (deliver's keep)
};

// Rank 0's own devices take their tiles straight from the ranks' scheduler.
class RankZeroTiles : public TileSource {
public:
    explicit RankZeroTiles(RankTiles& ranks) : ranks_(ranks) {}
    bool next(TileRect& tile) override {
        std::vector<TileRect> tiles = ranks_.handOut(0, 1);
        if (tiles.empty()) return false;
        tile = tiles.front();
        return true;
    }

private:
    RankTiles& ranks_;
};

// Rank 0's own share, on its own thread: rounds of the engine until the frame is complete
// (a second round only when a failed or dropped rank's tiles came back after the first
// ended). Rank 0's tiles have no deadline: its devices are in this process, and a hung
// one is the engine's to handle.
struct LocalShare {
    std::atomic<bool> done{false};
    std::atomic<int> tilesKept{0};
    std::atomic<bool> stop{false};
    std::mutex mutex;
    std::vector<RenderStats> rounds;
    std::string failure;  // every device of rank 0 failed
};

void renderLocalShare(Prepared& p, RankTiles& ranks, LocalShare& share) {
    TileScheduler& scheduler = ranks.scheduler;
    try {
        OpenClFrameSource frames(p.devices);  // the scene packed once, for every round
        while (!share.stop && !interrupted() && !scheduler.complete()) {
            if (!scheduler.anyToHandOut(0)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                continue;
            }
            RankZeroTiles tiles(ranks);
            RenderStats round = renderShare(frames, p, frameRequest(p, tiles, [&](const FinishedTile& tile) {
                                                if (ranks.deliver(0, tile.rect, tile.rgb, tile.rect.pixels() * 3))
                                                    ++share.tilesKept;
                                            }));
            std::lock_guard lock(share.mutex);
            share.rounds.push_back(std::move(round));
        }
    } catch (...) {
        scheduler.giveBack(0);
        std::lock_guard lock(share.mutex);
        share.failure = describeFailure(std::current_exception()).message;
    }
    share.done = true;
}

// One rank's statistics from the engine's rounds on rank 0: devices summed over rounds.
RenderStats sumRounds(const std::vector<RenderStats>& rounds) {
    RenderStats total;
    for (const RenderStats& r : rounds) {
        total.primaryRays += r.primaryRays;
        total.shadowRays += r.shadowRays;
        total.secondaryRays += r.secondaryRays;
        total.bvhBuildSeconds += r.bvhBuildSeconds;
        total.kernelBuildSeconds += r.kernelBuildSeconds;
        total.uploadSeconds += r.uploadSeconds;
        total.warnings.insert(total.warnings.end(), r.warnings.begin(), r.warnings.end());
        if (total.devices.empty()) total.devices = r.devices;
        else
            for (size_t i = 0; i < r.devices.size() && i < total.devices.size(); ++i) {
                DeviceStats& d = total.devices[i];
                d.tiles += r.devices[i].tiles;
                d.pixels += r.devices[i].pixels;
                d.rays += r.devices[i].rays;
                d.busySeconds += r.devices[i].busySeconds;
                d.failed = d.failed || r.devices[i].failed;
                if (d.failure.empty()) d.failure = r.devices[i].failure;
            }
    }
    return total;
}

// A job whose image was written whole, but that rank 0 ended (MPI_Abort) because a rank
// stopped answering: mpirun would otherwise wait for it in MPI_Finalize forever.
constexpr int kExitRankAbandoned = 4;
// How often rank 0 looks for tiles past their deadline.
constexpr double kDeadlineCheckSeconds = 0.1;

// "rank 2 (host h)"; a rank silent since the start-up has no known host.
std::string rankName(int rank, const std::vector<std::string>& hosts) {
    const bool known = size_t(rank) < hosts.size() && !hosts[size_t(rank)].empty();
    return "rank " + std::to_string(rank) + (known ? " (host " + hosts[size_t(rank)] + ")" : std::string());
}

std::string formatSeconds(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f s", seconds);
    return text;
}

// The job is over for the ranks that answer (the image written, or failed for its own
// reason, or the start-up refused): end those that never answered. MPI_Finalize and
// mpirun would wait for them for ever; MPI_Abort makes mpirun end every rank, and exits
// with the code given here (a success becomes kExitRankAbandoned).
[[noreturn]] void endJobWithout(const std::vector<int>& silent, int code, const std::vector<std::string>& hosts,
                                bool imageWritten, const TestHooks& hooks) {
    std::string names;
    for (int r : silent) names += (names.empty() ? "" : ", ") + rankName(r, hosts);
    const int exitCode = code == 0 ? kExitRankAbandoned : code;
    std::cerr << "ray: ending the job without " << names << ", which did not answer"
              << (code == 0 && imageWritten ? " (the image is written and whole)" : "") << "; exit " << exitCode
              << "\n"
              << std::flush;
    // Test hook: a later abort, so that the workers told to end surely wait for it (awaitAbort).
    if (hooks.abortAfterSeconds > 0) std::this_thread::sleep_for(std::chrono::duration<double>(hooks.abortAfterSeconds));
    MPI_Abort(MPI_COMM_WORLD, exitCode);
    std::_Exit(exitCode);
}

class Coordinator {
public:
    // `silentAtStart`: the workers that never finished their start-up (startCoordinator),
    // already named; they get no tiles, and the job ends without them.
    Coordinator(Prepared& p, const MpiSession& mpi, int tileSide, std::vector<std::string> hosts,
                const std::vector<int>& silentAtStart, const TestHooks& hooks)
        : p_(p), mpi_(mpi), hooks_(hooks), ranks_(p.options.settings.width, p.options.settings.height, tileSide),
          rankStats_(size_t(mpi.size)), tilesPerRank_(size_t(mpi.size), 0), abandoned_(size_t(mpi.size), false),
          hosts_(std::move(hosts)), lastHeard_(size_t(mpi.size), Clock::now()) {
        if (p.options.rankTimeout > 0) scheduler_.setDeadline(p.options.rankTimeout);
        for (int r : silentAtStart) {
            abandoned_[size_t(r)] = true;
            scheduler_.drop(r);
        }
    }

    int run() {
        ProgressBar progress(!p_.options.quiet);
        beginRendering();
        const auto start = Clock::now();
        LocalShare share;
        std::thread local([&] { renderLocalShare(p_, ranks_, share); });
        auto lastCheck = Clock::now();
        while (!interrupted()) {
            const bool handled = handleOneMessage();
            if (secondsSince(lastCheck) >= kDeadlineCheckSeconds) {
                abandonUnresponsiveRanks();
                lastCheck = Clock::now();
            }
            if (handled) continue;
            progress.update(scheduler_.fractionDone());
            // Rank 0's share ends when the frame is complete or its devices all failed.
            if (share.done && everyWorkerAccountedFor()) break;
            idle();
        }
        share.stop = true;
        local.join();
        progress.finish();
        const double renderSeconds = secondsSince(start);

        RenderedFrame result;
        result.cancelled = interrupted();
        const bool complete = scheduler_.complete();
        result.image = ranks_.takeImage();
        int code = 0;
        if (!result.cancelled && !complete) {
            std::cerr << "ray: every rank's OpenCL devices failed or stopped answering; rank 0: " << share.failure
                      << "\n";
            code = kExitRuntime;
        } else {
            result.stats = collectStats(share);
            result.stats.renderSeconds = renderSeconds;
            try {
                code = finishRender(result, p_.output, p_.options);
            } catch (...) {
                code = reportFailure(std::current_exception());
            }
        }
        if (result.cancelled) leaveInterrupted();
        std::vector<int> silent;
        for (int r = 1; r < mpi_.size; ++r)
            if (!rankStats_[size_t(r)]) silent.push_back(r);
        for (int r = 1; r < mpi_.size; ++r)
            if (rankStats_[size_t(r)]) sendDecision({code, !silent.empty()}, r, kEnd);
        if (!silent.empty()) endJobWithout(silent, code, hosts_, !result.cancelled && complete && code == 0, hooks_);
        return code;
    }

private:
    std::string nameOf(int rank) const { return rankName(rank, hosts_); }

    bool everyWorkerAccountedFor() const {
        for (int r = 1; r < mpi_.size; ++r)
            if (!rankStats_[size_t(r)] && !abandoned_[size_t(r)]) return false;
        return true;
    }

    // A worker holding a tile past its deadline, or silent (not even a heartbeat) for the
    // usual deadline, is taken for hung: named, given no more tiles, its tiles to the others.
    void abandonUnresponsiveRanks() {
        for (const TileScheduler::Late& late : scheduler_.lateWorkers()) {
            if (late.worker == 0 || rankStats_[size_t(late.worker)]) continue;
            abandon(late.worker, "held its tile at (" + std::to_string(late.tile.x) + ", " + std::to_string(late.tile.y) +
                                   ") for " + formatSeconds(late.heldSeconds) + ", past its deadline of " +
                                   formatSeconds(late.deadlineSeconds));
        }
        // A worker that answers sends a heartbeat every kHeartbeatSeconds until it has sent
        // its statistics, even while its kernel compiles (its tiles then wait for their first
        // result up to kFirstTileSeconds): silence for the usual deadline, not the first
        // tile's, means it stopped, whatever it was doing. Also once the image is complete,
        // when it holds no tile that counts but its statistics are due.
        const double limit = scheduler_.usualDeadline();
        for (int r = 1; r < mpi_.size; ++r) {
            const double silence = secondsSince(lastHeard_[size_t(r)]);
            if (!rankStats_[size_t(r)] && !abandoned_[size_t(r)] && silence > limit)
                abandon(r, "sent nothing for " + formatSeconds(silence) + ", not even a heartbeat (its deadline: " +
                               formatSeconds(limit) + ")" +
                               (scheduler_.complete() ? ", and the image is complete without it" : ""));
        }
    }

    void abandon(int rank, const std::string& why) {
        abandoned_[size_t(rank)] = true;
        const int moved = scheduler_.drop(rank);
        std::cerr << "ray: warning: " << nameOf(rank) << " does not answer: it " << why << "; it gets no more tiles ("
                  << moved << " of its tiles went to the other ranks; --rank-timeout sets the deadline)\n"
                  << std::flush;
    }

private:
    // Handles the next message if one is waiting; false when none is.
    bool handleOneMessage() {
        int flag = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
        if (!flag) return false;
        const auto start = Clock::now();
        const int from = status.MPI_SOURCE;
        lastHeard_[size_t(from)] = start;
        int bytes = 0;
        MPI_Get_count(&status, MPI_BYTE, &bytes);
        messages_ += 1;
        bytes_ += uint64_t(bytes);
        switch (status.MPI_TAG) {
            case kRequest: answerRequest(from); break;
            case kResult: receiveResult(from, bytes); break;
            case kFinished: receiveFinished(from); break;
            case kAlive: MPI_Recv(nullptr, 0, MPI_INT, from, kAlive, MPI_COMM_WORLD, MPI_STATUS_IGNORE); break;
            // A rank left out of the frame for its silent start-up, that answers after all:
            // it waits for a start that never comes, and is ended with the job.
            case kHello: receiveText(from, kHello); break;
            default: abortAll(0, "unexpected message (tag " + std::to_string(status.MPI_TAG) + ") from rank " + std::to_string(from));
        }
        dispatchSeconds_ += secondsSince(start);
        return true;
    }

    void answerRequest(int from) {
        int count = 0;
        MPI_Recv(&count, 1, MPI_INT, from, kRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        std::vector<int> values;
        for (const TileRect& t : ranks_.handOut(from, std::clamp(count, 0, 1024)))
            values.insert(values.end(), {t.x, t.y, t.width, t.height});
        MPI_Send(values.data(), int(values.size()), MPI_INT, from, kTiles, MPI_COMM_WORLD);
        messages_ += 1;
        bytes_ += values.size() * sizeof(int);
    }

    // A tile message is received into floats, so that its pixels are pasted from where they
    // arrived (the header is a whole number of floats).
    void receiveResult(int from, int bytes) {
        static_assert(sizeof(TileResultHeader) % sizeof(float) == 0);
        constexpr size_t kHeaderFloats = sizeof(TileResultHeader) / sizeof(float);
        buffer_.resize((size_t(std::max(bytes, 0)) + sizeof(float) - 1) / sizeof(float));
        MPI_Recv(buffer_.data(), bytes, MPI_BYTE, from, kResult, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (size_t(bytes) < sizeof(TileResultHeader)) abortAll(0, "a short tile message from rank " + std::to_string(from));
        TileResultHeader header;
        std::memcpy(&header, buffer_.data(), sizeof header);
        const TileRect rect{header.x, header.y, header.width, header.height};
        const size_t floats = (size_t(bytes) - sizeof header) / sizeof(float);
        try {
            if (ranks_.deliver(from, rect, buffer_.data() + kHeaderFloats, floats)) {
                // The rays of the tiles kept: those of a rank that failed later count too.
                ++tilesPerRank_[size_t(from)];
                workerRays_.primaryRays += header.primaryRays;
                workerRays_.shadowRays += header.shadowRays;
                workerRays_.secondaryRays += header.secondaryRays;
            }
        } catch (const std::invalid_argument& e) {
            abortAll(0, e.what());
        }
    }

    // A worker's statistics: kept, merged in rank order at the end (collectStats).
    void receiveFinished(int from) {
        Json message;
        try {
            message = Json::parse(receiveText(from, kFinished));
        } catch (const Json::exception& e) {
            abortAll(0, "unreadable statistics from rank " + std::to_string(from) + ": " + e.what());
        }
        std::string failure = message.value("failure", "");
        if (failure.rfind("ray: ", 0) == 0) failure.erase(0, 5);
        if (!failure.empty()) {
            const int givenBack = scheduler_.giveBack(from);
            dropWarnings_.push_back("rank " + std::to_string(from) + " dropped (" + std::to_string(givenBack) +
                                    " tiles given to the others): " + failure);
        }
        rankStats_[size_t(from)] = std::move(message);
    }

    RenderStats collectStats(LocalShare& share) {
        RenderStats stats;
        std::lock_guard lock(share.mutex);
        const RenderStats own = sumRounds(share.rounds);
        rankStats_[0] = statsToMessage(own, p_.loadSeconds, share.failure);
        if (!share.failure.empty()) stats.warnings.push_back("rank 0 dropped: " + share.failure);
        for (size_t rank = 0; rank < rankStats_.size(); ++rank)
            if (rankStats_[rank]) mergeRankStats(stats, int(rank), *rankStats_[rank]);
        stats.warnings.insert(stats.warnings.end(), dropWarnings_.begin(), dropWarnings_.end());
        stats.primaryRays = own.primaryRays + workerRays_.primaryRays;
        stats.shadowRays = own.shadowRays + workerRays_.shadowRays;
        stats.secondaryRays = own.secondaryRays + workerRays_.secondaryRays;

        const RenderSettings& s = p_.options.settings;
        stats.width = s.width;
        stats.height = s.height;
        stats.depth = s.maxDepth;
        stats.samples = maxSamplesPerPixel(s);
        stats.loadSeconds = p_.loadSeconds;
        stats.device = std::to_string(mpi_.size) + " MPI ranks, " + std::to_string(stats.devices.size()) +
                       " OpenCL devices";
        DistributionStats& d = stats.distribution;
        d.ranks = mpi_.size;
        d.tiles = scheduler_.tileCount();
        d.tilesPerRank = tilesPerRank_;
        d.tilesPerRank[0] = share.tilesKept;
        d.messages = messages_;
        d.bytes = bytes_;
        d.dispatchSeconds = dispatchSeconds_;
        return stats;
    }

    Prepared& p_;
    const MpiSession& mpi_;
    const TestHooks& hooks_;
    RankTiles ranks_;
    TileScheduler& scheduler_ = ranks_.scheduler;
    std::vector<std::optional<Json>> rankStats_;  // each worker's, once it finished; rank 0's at the end
    std::vector<int> tilesPerRank_;
    std::vector<std::string> dropWarnings_;  // workers whose devices all failed
    std::vector<bool> abandoned_;            // workers taken for hung (abandonUnresponsiveRanks)
    std::vector<std::string> hosts_;         // each rank's host, for the messages
    std::vector<Clock::time_point> lastHeard_;  // each worker's latest message
    struct {
        uint64_t primaryRays = 0, shadowRays = 0, secondaryRays = 0;
    } workerRays_;  // the rays of the workers' tiles kept
    std::vector<float> buffer_;
    uint64_t messages_ = 0, bytes_ = 0;
    double dispatchSeconds_ = 0;
};

std::string processorName() {
    char name[MPI_MAX_PROCESSOR_NAME] = {};
    int length = 0;
    MPI_Get_processor_name(name, &length);
    return std::string(name, strnlen(name, MPI_MAX_PROCESSOR_NAME));
}

// The start-up, without a collective: a rank stopped before a collective would hold every
// other rank in it for ever. Each worker prepares (parses the command line, loads the
// scene, opens its devices) on another thread while its main thread sends heartbeats, then
// says hello to rank 0: its outcome, fingerprint and host. Rank 0 decides for every rank
// (kStart) once each worker has said hello or has been silent for the usual deadline.

// A worker's start-up; the exit code to end with, 0 to render.
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
            MPI_Send(nullptr, 0, MPI_INT, 0, kAlive, MPI_COMM_WORLD);
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

// Rank 0's start-up: the exit code every rank ends with (0: render), each rank's host, and
// the workers that never said hello (named; the frame goes on without them). When the
// start fails, the first rank that failed (in rank order) says why, through rank 0 alone.
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
    if (byAbort) endJobWithout(silent, code, hosts, false, hooks);
    return code;
}

}  // namespace

int runDistributedCommand(int argc, char** argv, const std::vector<std::string>& args) {
    MpiSession mpi(argc, argv);
    Prepared prepared;
    const TestHooks& hooks = testHooks();
    try {
        if (mpi.rank != 0) {
            if (int code = startWorker(prepared, args, mpi.rank, hooks); code != 0) return code;
            if (prepared.nothingToRender) return 0;
            return runWorker(prepared, hooks);
        }
        std::vector<std::string> hosts;
        std::vector<int> silent;
        if (int code = startCoordinator(prepared, args, mpi, hosts, silent, hooks); code != 0) return code;
        if (prepared.nothingToRender) return 0;
        return Coordinator(prepared, mpi, tileSideOf(prepared), std::move(hosts), silent, hooks).run();
    } catch (...) {
        abortAll(mpi.rank, describeFailure(std::current_exception()).message);
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
