#include "opencl/opencl_engine.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>

#include "core/memory_limits.h"
#include "opencl/kernel_arguments.h"
#include "opencl/kernel_variant.h"
#include "opencl/scene_packing.h"
#include "render/device_error.h"
#include "render/tile_scheduler.h"
#include "render/tile_side.h"

namespace ray {

namespace {

using Clock = std::chrono::steady_clock;

constexpr size_t kTilesInFlight = 4;  // per device: it never idles between launches

Clock::duration inClockTicks(double seconds) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string mebibytes(uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

// Refuses, before any upload, a scene whose buffers (those its kernel reads) exceed what the
// device allows.
void checkDeviceLimits(const OpenClDevice& device, const KernelVariant& variant, const PackedScene& packed,
                       size_t tileBytes) {
    const std::string advice = "; use a smaller scene or image, another device (ray --list-devices), or --device ref";
    auto checkAllocation = [&](const char* what, size_t bytes) {
        if (bytes > device.maxAllocation)
            throw DeviceError("the scene's " + std::string(what) + " need a " + mebibytes(bytes) +
                              " buffer, more than the " + mebibytes(device.maxAllocation) + " " +
                              device.description() + " allows in one allocation" + advice);
    };
    uint64_t sceneBytes = 0;
    packed.forEachBuffer([&](const auto& table, SceneBufferName name) {
        if (!variant.reads(name)) return;
        checkAllocation(name.what, table.size() * sizeof(table[0]));
        sceneBytes += table.size() * sizeof(table[0]);
    });
    checkAllocation("tile", tileBytes);
    // Each launch in flight has its colors and ray counts: two buffers of tileBytes.
    uint64_t total = sceneBytes + 2 * kTilesInFlight * uint64_t(tileBytes);
    if (total > device.globalMemory)
        throw DeviceError("the scene needs " + mebibytes(total) + " of device memory, more than the " +
                          mebibytes(device.globalMemory) + " of " + device.description() + advice);
    // On the host: a tile's buffers read back, and on a CPU device its tile outputs too (it
    // reads the scene's tables where they are: uploadBuffer).
    const uint64_t outputs = 2 * kTilesInFlight * uint64_t(tileBytes);
    uint64_t hostBytes = 2 * uint64_t(tileBytes) + (device.isCpu ? outputs : 0);
    if (auto shortfall = hostMemoryShortfall(hostBytes))
        throw DeviceError("rendering on " + device.description() + " " + *shortfall + " on the host" + advice);
}

// A table of the packed scene as a device buffer. A CPU device reads the host's table in
// place (CL_MEM_USE_HOST_PTR: PoCL then neither copies nor allocates; recursiveSpheres10's
// 0.35 s and 400 MB of copies are gone), so the table must stay unchanged and alive while
// the buffer lives (DeviceSlot::releaseScene). Other devices get a copy in their memory.
// OpenCL refuses zero-sized buffers; an empty table gets one unused element.
template <typename T>
cl::Buffer uploadBuffer(const cl::Context& context, const std::vector<T>& data, bool inPlace) {
    static const T placeholder{};
    const void* source = data.empty() ? static_cast<const void*>(&placeholder) : data.data();
    size_t bytes = std::max<size_t>(1, data.size()) * sizeof(T);
    const cl_mem_flags flags = CL_MEM_READ_ONLY | (inPlace ? CL_MEM_USE_HOST_PTR : CL_MEM_COPY_HOST_PTR);
    return cl::Buffer(context, flags, bytes, const_cast<void*>(source));
}

// A test hook: RAY_TEST_COPY_SCENE=1 gives a CPU device a copy of the scene too
// (CL_MEM_COPY_HOST_PTR). Oclgrind's --uninitialized takes a CL_MEM_USE_HOST_PTR buffer
// for never written (tests/oclgrind.sh), so its run sets this; the kernel reads the same bytes.
bool sceneCopiedForTests() {
    const char* value = std::getenv("RAY_TEST_COPY_SCENE");
    return value && *value;
}

// A test hook: RAY_TEST_BVH_SHORT_STACK=N builds the kernel with an N-entry traversal
// stack (cl/traversal/stack.cl BvhStack), so that tests can make every walk overflow and show
// that the fallback finds the same hits. Empty unless set to a number from 1 to 64.
std::string shortStackOption() {
    const char* value = std::getenv("RAY_TEST_BVH_SHORT_STACK");
    if (!value) return "";
    char* end = nullptr;
    long entries = std::strtol(value, &end, 10);
    if (end == value || *end != '\0' || entries < 1 || entries > 64)
        throw std::invalid_argument("RAY_TEST_BVH_SHORT_STACK must be a number from 1 to 64, not '" +
                                    std::string(value) + "'");
    return " -DRAY_BVH_SHORT_STACK=" + std::to_string(entries);
}

// A test hook: RAY_CPU_PACKETS=0 keeps a CPU device on one ray per work-item, and 4, 8 or
// 16 sets its packet width (kernelVariantFor; tests/cpu_paths.sh compares the paths' images).
std::optional<int> cpuLanesForTests() {
    const std::string setting = std::getenv("RAY_CPU_PACKETS") ? std::getenv("RAY_CPU_PACKETS") : "";
    if (setting == "0") return 1;
    if (setting == "4" || setting == "8" || setting == "16") return std::stoi(setting);
    return std::nullopt;
}

std::string buildOptions(int maxDepth, const KernelVariant& variant) {
    // One frame per bounce plus the camera ray (cl/render/ray_tree.cl). No
    // -cl-fast-relaxed-math: the intersection code relies on IEEE infinities.
    return "-cl-std=CL1.2 -DRAY_MAX_FRAMES=" + std::to_string(maxDepth + 1) + shortStackOption() +
           variant.buildDefine();
}

DeviceError describeClError(const OpenClDevice& device, const cl::Error& e) {
    std::string what = openClErrorName(e.err());
    std::string advice = (e.err() == CL_MEM_OBJECT_ALLOCATION_FAILURE || e.err() == CL_OUT_OF_RESOURCES ||
                          e.err() == CL_OUT_OF_HOST_MEMORY)
                             ? "the device ran out of memory; try a smaller image or scene, or --device ref"
                             : "try another device (ray --list-devices) or --device ref";
    return DeviceError(device.description() + ": " + e.what() + " failed with " + what + "; " + advice);
}

// Test hooks, read from the environment for each device of a frame (opencl_engine.h).
struct TestHooks {
    std::optional<int> failAfterTiles;    // RAY_TEST_FAIL_DEVICE="k:n"
    std::optional<int> hangAfterTiles;    // RAY_TEST_HANG_DEVICE="k:n"
    std::optional<int> slowBuildSeconds;   // RAY_TEST_SLOW_BUILD="k:s"
};

// "k:n" in the variable, for device k of the selection (0-based): n, else nothing.
std::optional<int> hookValue(const char* variable, int deviceSlot) {
    const char* hook = std::getenv(variable);
    if (!hook) return std::nullopt;
    int k = -1, n = -1;
    if (std::sscanf(hook, "%d:%d", &k, &n) != 2 || k != deviceSlot || n < 0) return std::nullopt;
    return n;
}

TestHooks testHooksFor(int deviceSlot) {
    return {hookValue("RAY_TEST_FAIL_DEVICE", deviceSlot), hookValue("RAY_TEST_HANG_DEVICE", deviceSlot),
            hookValue("RAY_TEST_SLOW_BUILD", deviceSlot)};
}

// When a device that has tiles in flight counts as hung (see opencl_engine.h): no tile back
// for kDeadlineFactor times the slowest tile seen, and at least kDeadlineFloorSeconds (a
// machine busy with other work, a tile far heavier than those before it). A device's first
// tile with a program also compiles it for the launch (PoCL: about 14 s for this kernel, cold,
// on a loaded 2-core machine), so it gets kWarmUpSeconds, and a frame never waits for it.
constexpr double kDeadlineFactor = 10;
constexpr double kDeadlineFloorSeconds = 10;
constexpr double kWarmUpSeconds = 300;

struct Frame;

// What one device keeps between frames: its context, queue, uploaded scene, programs, and
// the host thread that serves it. Shared by the engine and that thread, which may outlive
// the engine: a hung device's thread cannot be joined (opencl_engine.h).
struct DeviceSlot {
    OpenClDevice device;
    int index = 0;  // position in the engine's selection
    KernelVariant variant;  // what its kernel runs (kernelVariantFor): the kernel's build, launches and tables

    // The thread's mailbox, under `mutex`.
    std::mutex mutex;
    std::condition_variable wake;
    std::shared_ptr<Frame> frame;  // the frame to serve next
    uint64_t frameNumber = 0;             // that frame's number: a new one wakes the thread
    bool stop = false;                    // the engine is gone
    bool busy = false;                    // serving a frame (preparing, rendering or hung)
    bool dropped = false, hung = false;
    std::string failure;                  // why it was dropped
    bool failureReported = false;         // in some frame's warnings
    std::thread thread;

    // Touched only by the thread (or by the engine while the thread is idle).
    cl::Context context;
    cl::CommandQueue queue;
    std::shared_ptr<const PackedScene> uploaded;  // the packing the scene's buffers are up to date with
    size_t checkedTilePixels = 0;  // the tile size checkDeviceLimits last passed with them
    // The scene's buffers, in the order of PackedScene::forEachBuffer (renderTile's), each
    // with the version of the table it holds and the packing it was uploaded from: after an
    // edit a buffer whose table kept its version is kept, and a CPU device, which reads the
    // table in place, keeps that packing alive with it.
    std::array<cl::Buffer, kSceneBufferCount> sceneBuffers;
    std::array<uint64_t, kSceneBufferCount> bufferVersions{};
    std::array<std::shared_ptr<const PackedScene>, kSceneBufferCount> bufferOwners;
    // Lets go of the scene's buffers: before the packed tables they may use in place change.
    void releaseScene() {
        sceneBuffers = {};
        bufferVersions = {};
        bufferOwners = {};
        uploaded.reset();
    }
    // Launch k writes its tile into outputs[k % kTilesInFlight]: tile-sized buffers, so a
    // frame costs the device (and, on a CPU device, the host) a few tiles, not two
    // full-frame copies of the image (32 bytes a pixel: 25 MB at 1024x768, 265 MB at 4K).
    // Each also holds the host copies its reads fill, kept from launch to launch: a tile's
    // fresh vectors cost page faults and zeroing on every tile.
    struct TileOutput {
        cl::Buffer colors, counts;
        std::vector<cl_float4> hostColors;
        std::vector<cl_uint4> hostCounts;
        size_t pixels = 0, rayCounts = 0;  // the entries each holds (TileEntries)
    };
    std::array<TileOutput, kTilesInFlight> outputs;
    // The packet path's block queue (cl/kernel.cl): two counters, zero between launches.
    cl::Buffer blockQueue;
    struct Program {
        KernelProgram program;
        cl::Kernel kernel;
        bool warm = false;  // a tile came back: the launch-time compile is behind it
        // The driver's CL_KERNEL_PRIVATE_MEM_SIZE: private memory a work-item (the GPU
        // budget of docs/performance.md, "The kernel on GPUs"; scripts/gpu_check.sh reports it).
        uint64_t privateBytes = 0;
    };
    std::map<int, Program> programs;  // by maximum depth
    double slowestTileSeconds = 0;    // the slowest tile it has rendered (warm-up tiles aside)
    std::optional<cl::UserEvent> neverSet;  // RAY_TEST_HANG_DEVICE: what its launches wait for

    // The programs go under the lock of the PoCL builds: PoCL frees a program's LLVM module
    // as it goes, and LLVM 15 must not do that while another thread parses bitcode (a PoCL
    // device still building as the process ended, the other done with the frame: the
    // corpus on --device all with POCL_DEVICES="pthread pthread" aborted with "LLVM ERROR:
    // out of memory" in UpgradeIntrinsicFunction, once or twice a run). While a build holds
    // the lock, they are left for the process's end rather than waited for: a cold build
    // takes seconds, and an interrupted ray exits at once.
    ~DeviceSlot() {
        const std::unique_lock released = poclCompilerLock(device, false);
        if (device.isPocl && !released.owns_lock()) new std::map<int, Program>(std::move(programs));  // kept
        programs.clear();
    }
};

// The state of one frame, shared by the engine's thread and the device threads. The caller's
// objects (options, source, image, stats) are touched only under `mutex` while the frame is
// open, or in source->next() while sourceCallers counts it: the engine closes the frame before
// renderFrame returns, and a device thread that was left behind (hung, still building) then
// touches nothing of the caller's.
//
// Which device renders which tile is the tile scheduler's (render/tile_scheduler.h), whose
// workers are the devices, by slot index: tiles given back by a failed or hung device first,
// copies of pending tiles at the end of the frame, the first result kept. The frame adds
// what only a device has: its launches in flight, in order, and when it counts as hung.
struct Frame {
    std::mutex mutex;
    std::condition_variable changed;
    bool closed = false;
    int sourceCallers = 0;  // device threads inside source->next()
    const FrameOptions* options = nullptr;
    // Where the tiles come from: null, the scheduler's own grid; else admitted to the
    // scheduler as the source gives them, until it has no more (sourceDone).
    TileSource* source = nullptr;
    bool sourceDone = false;
    std::optional<TileScheduler> scheduler;
    Image* image = nullptr;  // the frame: one of these two (FrameOptions::eightBit)
    ByteImage* bytes = nullptr;
    FrameStats* stats = nullptr;

    // What the devices prepare for; copies, so that a thread left behind may read them.
    std::shared_ptr<const PackedScene> packed;
    RenderSettings settings;
    gpu::RayRenderParams params{};
    int tileWidth = 0, tileHeight = 0;  // a full tile's (a guide: launches grow their buffers as needed)
    size_t tilePixels() const { return size_t(tileWidth) * size_t(tileHeight); }
    size_t workGroupSize = 8;

    uint64_t pixelsDone = 0, pixelsTotal = 0;
    double slowestTileSeconds = 0;  // any device's, this frame, warm-up tiles aside
    double uploadSeconds = 0, buildSeconds = 0;
    // When the first device began its tiles (its scene uploaded, its kernel built): where
    // the render's time starts, so that the statistics' kernel build and render are apart.
    std::optional<Clock::time_point> renderingSince;

    // One device's part in the frame.
    struct Flight {
        int tile;
        Clock::time_point launched;
    };
    enum class Part { Absent, Preparing, Rendering, Left, Failed, Hung };
    struct Participant {
        Part part = Part::Absent;
        TestHooks hooks;
        std::deque<Flight> flights;  // launched and not back, oldest first (they finish in order)
        Clock::time_point lastAnswer;
        bool warm = false;
        double slowestTileSeconds = 0;
        double busySeconds = 0;
    };
    std::vector<Participant> devices;  // by slot index
    int devicesLeft = 0;               // preparing or rendering

    bool cancelled() const { return options->cancel && options->cancel->load(); }
    bool allDone() const { return scheduler->complete(); }

    // When the device counts as hung if no tile comes back: nothing while it has none in flight.
    std::optional<Clock::time_point> deadline(const Participant& p) const {
        if (p.part != Part::Rendering || p.flights.empty()) return std::nullopt;
        const Clock::time_point since = std::max(p.flights.front().launched, p.lastAnswer);
        if (!p.warm) return since + inClockTicks(kWarmUpSeconds);
        double seconds =
            std::max(kDeadlineFloorSeconds, kDeadlineFactor * std::max(slowestTileSeconds, p.slowestTileSeconds));
        return since + inClockTicks(seconds);
    }
    bool late(const Participant& p, Clock::time_point now) const {
        auto d = deadline(p);
        return d && *d < now;
    }

    // The frame can return: its picture is complete (or cancelled) and no device that answers
    // still has a tile in flight, or no device is left. Devices still building, or compiling
    // their first launch, take no part and are not waited for.
    bool over() const {
        if (sourceCallers > 0) return false;
        if (devicesLeft == 0) return true;
        if (!allDone() && !cancelled()) return false;
        for (const Participant& p : devices)
            if (p.part == Part::Rendering && p.warm && !p.flights.empty()) return false;
        return true;
    }

    // Ends the device's part after a failure; its tiles go to the others.
    void deviceFailed(int index) {
        Participant& p = devices[size_t(index)];
        if (p.part != Part::Preparing && p.part != Part::Rendering) return;
        scheduler->giveBack(index);
        p.flights.clear();
        p.part = Part::Failed;
        --devicesLeft;
        changed.notify_all();
    }

    // Drops the devices past their deadline while another device is in the frame and not late
    // itself (a device that is the last one left is waited for: no other could take its
    // tiles). Returns them, with how long each was silent.
    struct Silent {
        int device;
        double seconds;
    };
    std::vector<Silent> dropLateDevices(Clock::time_point now) {
        std::vector<Silent> dropped;
        for (size_t i = 0; i < devices.size(); ++i) {
            Participant& p = devices[i];
            if (!late(p, now)) continue;
            bool another = false;
            for (size_t j = 0; j < devices.size(); ++j) {
                const Participant& q = devices[j];
                const bool in = q.part == Part::Preparing || q.part == Part::Rendering || q.part == Part::Left;
                if (j != i && in && !late(q, now)) another = true;
            }
            if (!another) continue;
            const Clock::time_point since = std::max(p.flights.front().launched, p.lastAnswer);
            dropped.push_back({int(i), std::chrono::duration<double>(now - since).count()});
            scheduler->drop(int(i));  // its tiles go to the others; its late answer still counts if first
            p.flights.clear();
            p.part = Part::Hung;
            --devicesLeft;
            changed.notify_all();
        }
        return dropped;
    }

    // The next moment a deadline passes after `now`, if any device has one ahead.
    std::optional<Clock::time_point> nextDeadline(Clock::time_point now) const {
        std::optional<Clock::time_point> next;
        for (const Participant& p : devices)
            if (auto d = deadline(p); d && *d > now && (!next || *d < *next)) next = d;
        return next;
    }
};

// What a launch writes for a tile of width x height: a color a pixel, and ray counts a
// work-item (a pixel's, or on the packet path a block's: cl/kernel.cl).
struct TileEntries {
    size_t pixels = 0, rayCounts = 0;
};
TileEntries tileEntries(int width, int height, int packetLanes) {
    const size_t pixels = size_t(width) * size_t(height);
    if (packetLanes <= 1) return {pixels, pixels};
    const int blockWidth = RAY_PIXEL_BLOCK_WIDTH(packetLanes), blockHeight = RAY_PIXEL_BLOCK_HEIGHT(packetLanes);
    return {pixels, size_t((width + blockWidth - 1) / blockWidth) * size_t((height + blockHeight - 1) / blockHeight)};
}

// Makes `out` hold a tile's entries, where it holds fewer: new buffers and host copies, each
// written through once (the fills run before the next launch), so that a kernel and a read
// find their pages in place. A page's first touch, in a kernel's work-items or a read, cost
// 4-13 µs on the 2-core VM of docs/performance.md; made here, at prepareDevice, for the
// frame's tiles, it is no longer the first tiles' (recursiveCones4 1024x768: render 0.124 ->
// 0.105 s).
void sizeTileOutput(DeviceSlot& slot, DeviceSlot::TileOutput& out, TileEntries tile) {
    const cl_uint zero = 0;
    // Host-allocatable: zero-copy reads on CPU devices (PoCL).
    if (out.pixels < tile.pixels) {
        out.colors = cl::Buffer(slot.context, CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR, tile.pixels * sizeof(cl_float4));
        slot.queue.enqueueFillBuffer(out.colors, zero, 0, tile.pixels * sizeof(cl_float4));
        out.hostColors.assign(tile.pixels, cl_float4{});
        out.pixels = tile.pixels;
    }
    if (out.rayCounts < tile.rayCounts) {
        out.counts = cl::Buffer(slot.context, CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR, tile.rayCounts * sizeof(cl_uint4));
        slot.queue.enqueueFillBuffer(out.counts, zero, 0, tile.rayCounts * sizeof(cl_uint4));
        out.hostCounts.assign(tile.rayCounts, cl_uint4{});
        out.rayCounts = tile.rayCounts;
    }
}

// One device's part of a frame, run on its thread once its kernel is built.
class DeviceWorker {
public:
    DeviceWorker(Frame& frame, DeviceSlot& slot) : frame_(frame), slot_(slot), index_(slot.index) {
        std::lock_guard lock(frame_.mutex);
        hooks_ = frame_.devices[size_t(index_)].hooks;
    }

    void run(cl::Kernel& kernel) {
        auto start = Clock::now();
        bool started = false;
        while (true) {
            if (hooks_.failAfterTiles && finished_ >= *hooks_.failAfterTiles)
                throw DeviceError(slot_.device.description() + ": failed on purpose (RAY_TEST_FAIL_DEVICE)");
            while (inFlight_.size() < kTilesInFlight) {
                std::optional<int> tile = acquire();
                if (!tile) break;
                if (!started) start = Clock::now(), started = true;
                launch(kernel, *tile);
            }
            if (inFlight_.empty()) {
                std::unique_lock lock(frame_.mutex);
                if (!taking()) break;
                if (frame_.cancelled() || frame_.allDone()) break;
                frame_.changed.wait_for(lock, std::chrono::milliseconds(50));
                continue;
            }
            finishOldest();
            busySeconds_ = secondsSince(start);
        }
        std::lock_guard lock(frame_.mutex);
        Frame::Participant& p = frame_.devices[size_t(index_)];
        slot_.slowestTileSeconds = p.slowestTileSeconds;
        p.busySeconds = busySeconds_;
        if (p.part == Frame::Part::Rendering) p.part = Frame::Part::Left;
        frame_.changed.notify_all();
    }

private:
    struct Launch {
        int tile;
        size_t output;        // index in slot_.outputs
        TileEntries entries;  // what it writes and reads back
        cl::Event read;       // the last of its reads back: done once the tile is on the host
    };

    // Under the frame's lock: the frame is open and this device still part of it.
    bool taking() const { return !frame_.closed && frame_.devices[size_t(index_)].part == Frame::Part::Rendering; }

    // The next tile for this device: one given back, else a fresh one (from the source when
    // the frame has one), else (when this device is idle) a copy of one still pending on
    // another device.
    std::optional<int> acquire() {
        std::unique_lock lock(frame_.mutex);
        if (!taking() || frame_.cancelled()) return std::nullopt;
        if (auto tile = take(TileScheduler::Copies::None)) return tile;
        if (frame_.source && !frame_.sourceDone) {
            ++frame_.sourceCallers;
            lock.unlock();
            TileRect rect;
            bool more = frame_.source->next(rect);  // may block (a distributed source)
            lock.lock();
            --frame_.sourceCallers;
            frame_.changed.notify_all();
            if (more) {
                frame_.scheduler->admit(rect);
            } else if (!frame_.sourceDone) {
                frame_.sourceDone = true;
                frame_.scheduler->closeAdmission();
            }
            if (auto tile = take(TileScheduler::Copies::None)) return tile;
        }
        if (!inFlight_.empty()) return std::nullopt;
        return take(TileScheduler::Copies::Allowed);  // the end of the frame
    }

    std::optional<int> take(TileScheduler::Copies copies) {
        const std::vector<int> tiles = frame_.scheduler->handOut(index_, 1, copies);
        if (tiles.empty()) return std::nullopt;
        frame_.devices[size_t(index_)].flights.push_back({tiles.front(), Clock::now()});
        return tiles.front();
    }

    // The launch's work-items: a pixel each, or on the packet path a work-group for each
    // compute unit, which take the tile's blocks from the queue (cl/kernel.cl).
    cl::NDRange globalSize(const TileRect& rect) const {
        const size_t group = frame_.workGroupSize;
        if (slot_.variant.lanes > 1) return cl::NDRange(group, group * std::max<size_t>(1, slot_.device.computeUnits));
        auto roundUp = [group](int n) { return (size_t(n) + group - 1) / group * group; };
        return cl::NDRange(roundUp(rect.width), roundUp(rect.height));
    }

    void launch(cl::Kernel& kernel, int tile) {
        const TileRect rect = frame_.scheduler->tile(tile);
        const size_t group = frame_.workGroupSize;
        gpu::RayRenderParams params = frame_.params;
        params.tile = {rect.x, rect.y, rect.width, rect.height};
        // At most kTilesInFlight launches, finished in order: this output's last user is done.
        const size_t output = launches_++ % kTilesInFlight;
        DeviceSlot::TileOutput& out = slot_.outputs[output];
        const TileEntries entries = tileEntries(rect.width, rect.height, slot_.variant.lanes);
        sizeTileOutput(slot_, out, entries);  // at prepareDevice for the frame's tiles
        // Arguments are captured at enqueue time.
        kernel.setArg(kernel_argument::kParams, sizeof(params), &params);
        kernel.setArg(kernel_argument::kTileColors, out.colors);
        kernel.setArg(kernel_argument::kTileRayCounts, out.counts);
        Launch l{tile, output, entries, {}};
        slot_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, globalSize(rect), cl::NDRange(group, group), hangHook());
        // The tile's reads go into the queue right behind its kernel, ahead of the launches
        // after it. A read enqueued once the kernel was done came after them all in the
        // in-order queue: the device ran dry before every tile came back, and waited idle
        // while the host pasted it and launched the next (PoCL, recursiveCones4: ~50 context
        // switches a tile).
        slot_.queue.enqueueReadBuffer(out.colors, CL_FALSE, 0, entries.pixels * sizeof(cl_float4), out.hostColors.data());
        slot_.queue.enqueueReadBuffer(out.counts, CL_FALSE, 0, entries.rayCounts * sizeof(cl_uint4),
                                      out.hostCounts.data(), nullptr, &l.read);
        slot_.queue.flush();
        inFlight_.push_back(l);
    }

    // RAY_TEST_HANG_DEVICE: the launches after its first n wait for an event that is never
    // set, as on a hung driver, and so does all that is queued after them (the queue is in
    // order): the device answers n tiles and its thread then blocks in clWaitForEvents, for
    // good. Called with this launch counted in launches_.
    const std::vector<cl::Event>* hangHook() {
        if (!hooks_.hangAfterTiles || launches_ <= size_t(*hooks_.hangAfterTiles)) return nullptr;
        if (!slot_.neverSet) slot_.neverSet = cl::UserEvent(slot_.context);
        hangingOn_ = {*slot_.neverSet};
        return &hangingOn_;
    }

    // Waits for the oldest launch, reads its tile back and keeps it unless another device
    // finished it first.
    void finishOldest() {
        Launch l = inFlight_.front();
        l.read.wait();
        const TileRect rect = frame_.scheduler->tile(l.tile);
        const size_t n = l.entries.pixels;
        const DeviceSlot::TileOutput& out = slot_.outputs[l.output];
        const std::vector<cl_float4>& rgba = out.hostColors;
        const std::vector<cl_uint4>& rays = out.hostCounts;
        inFlight_.pop_front();

        FinishedTile result;
        result.rect = rect;
        result.device = index_;
        rgb_.resize(n * 3);
        for (size_t p = 0; p < n; ++p)
            for (int c = 0; c < 3; ++c) rgb_[p * 3 + size_t(c)] = rgba[p].s[c];
        for (size_t e = 0; e < l.entries.rayCounts; ++e) {
            result.primaryRays += rays[e].s[0];
            result.shadowRays += rays[e].s[1];
            result.secondaryRays += rays[e].s[2];
        }
        result.rgb = rgb_.data();
        keep(l.tile, result);
    }

    // The device's answer: its tile time, then the tile unless another device was first.
    void answered(Frame::Participant& p, Clock::time_point now) {
        if (p.flights.empty()) return;  // dropped as hung: its tiles were taken back
        Frame::Flight f = p.flights.front();
        p.flights.pop_front();
        if (!p.warm) {
            p.warm = true;  // the first tile also compiled the program for the launch: no measure
            auto found = slot_.programs.find(frame_.settings.maxDepth);
            if (found != slot_.programs.end()) found->second.warm = true;
        } else {
            double seconds = std::chrono::duration<double>(now - std::max(f.launched, p.lastAnswer)).count();
            p.slowestTileSeconds = std::max(p.slowestTileSeconds, seconds);
            frame_.slowestTileSeconds = std::max(frame_.slowestTileSeconds, seconds);
        }
        p.lastAnswer = now;
    }

    void keep(int tile, const FinishedTile& result) {
        const Clock::time_point now = Clock::now();
        std::lock_guard lock(frame_.mutex);
        if (frame_.closed) return;
        answered(frame_.devices[size_t(index_)], now);
        const TileRect& r = result.rect;
        const bool first = frame_.scheduler->deliver(index_, tile, [&] {
            if (frame_.bytes)
                pasteTile(*frame_.bytes, r, result.rgb);
            else
                pasteTile(*frame_.image, r, result.rgb);
        });
        // The engine's thread and the devices with no tile in flight wait for the frame's
        // end (Frame::over, allDone): a tile kept before then changes nothing they wait on,
        // and waking the engine for each took a core from the device's threads (PoCL on 2
        // cores: a context switch a tile). Its deadlines only move later meanwhile.
        if (frame_.allDone()) frame_.changed.notify_all();
        if (!first) {
            ++frame_.stats->duplicatesDropped;
            return;
        }
        ++finished_;
        FrameStats& s = *frame_.stats;
        s.primaryRays += result.primaryRays;
        s.shadowRays += result.shadowRays;
        s.secondaryRays += result.secondaryRays;
        DeviceStats& d = s.devices[size_t(index_)];
        ++d.tiles;
        d.kernelPrivateBytes = slot_.programs.at(frame_.settings.maxDepth).privateBytes;
        d.pixels += uint64_t(r.width) * uint64_t(r.height);
        d.rays += result.primaryRays + result.shadowRays + result.secondaryRays;
        frame_.pixelsDone += uint64_t(r.width) * uint64_t(r.height);
        if (frame_.options->onTile) frame_.options->onTile(result);
        if (frame_.options->progress && frame_.pixelsTotal > 0)
            frame_.options->progress(std::min(1.0, double(frame_.pixelsDone) / double(frame_.pixelsTotal)));
    }

    Frame& frame_;
    DeviceSlot& slot_;
    int index_;
    TestHooks hooks_;
    std::deque<Launch> inFlight_;
    std::vector<cl::Event> hangingOn_;
    std::vector<float> rgb_;  // the tile being kept, as FinishedTile has it
    size_t launches_ = 0;
    int finished_ = 0;  // tiles kept
    double busySeconds_ = 0;
};

// Runs a newly built program's kernel once on a tile of no pixels, the scene's buffers bound
// (buildKernelProgram's firstRun): PoCL finishes building a kernel at its first launch,
// where it compiles (or takes from its cache) the work-group function for the launch's
// local size, and PoCL devices must do that one at a time. It also keeps that work out of
// the frame's first tile.
void launchOnNoPixels(const DeviceSlot& slot, const cl::Program& program, const gpu::RayRenderParams& frameParams,
                      size_t group) {
    cl::Kernel kernel(program, "renderTile");
    gpu::RayRenderParams params = frameParams;
    params.tile = {0, 0, 0, 0};  // every work-item returns before it reads or writes a buffer
    kernel.setArg(kernel_argument::kParams, sizeof(params), &params);
    for (size_t i = 0; i < kSceneBufferCount; ++i)
        kernel.setArg(kernel_argument::kFirstSceneBuffer + cl_uint(i), slot.sceneBuffers[i]);
    cl::Buffer unwritten(slot.context, CL_MEM_WRITE_ONLY, sizeof(cl_float4) + sizeof(cl_uint4));
    kernel.setArg(kernel_argument::kTileColors, unwritten);
    kernel.setArg(kernel_argument::kTileRayCounts, unwritten);
    if (slot.variant.lanes > 1) kernel.setArg(kernel_argument::kBlockQueue, slot.blockQueue);
    slot.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(group, group), cl::NDRange(group, group));
    slot.queue.finish();
}

// Uploads the scene (when the device holds another packing), sizes the output buffers,
// builds (or reuses) the program for the frame's depth and binds the buffers. Reports the
// seconds spent uploading and building to the frame.
cl::Kernel& prepareDevice(DeviceSlot& slot, Frame& frame, const TestHooks& hooks) {
    const PackedScene& packed = *frame.packed;
    if (slot.uploaded != frame.packed || slot.checkedTilePixels != frame.tilePixels()) {
        checkDeviceLimits(slot.device, slot.variant, packed, frame.tilePixels() * sizeof(cl_float4));
        slot.checkedTilePixels = frame.tilePixels();
    }
    if (!slot.context()) {
        slot.context = cl::Context(slot.device.device);
        slot.queue = cl::CommandQueue(slot.context, slot.device.device);
        if (slot.variant.lanes > 1) {
            cl_uint empty[2] = {0, 0};
            slot.blockQueue = cl::Buffer(slot.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof(empty), empty);
        }
    }
    double uploadSeconds = 0, buildSeconds = 0;
    auto start = Clock::now();
    if (slot.uploaded != frame.packed) {
        // Only the tables this packing changed (a new packing changes every one).
        const bool inPlace = slot.device.isCpu && !sceneCopiedForTests();
        size_t next = 0;
        bool uploadedAny = false;
        packed.forEachBuffer([&](const auto& table, SceneBufferName name) {
            const size_t i = next++;
            if (slot.sceneBuffers[i]() && slot.bufferVersions[i] == packed.versions[i]) return;
            slot.sceneBuffers[i] = cl::Buffer();  // before its table's owner may go
            slot.bufferOwners[i].reset();
            const std::remove_cvref_t<decltype(table)> unread;  // a table the device's kernel never reads
            slot.sceneBuffers[i] = uploadBuffer(slot.context, slot.variant.reads(name) ? table : unread, inPlace);
            slot.bufferVersions[i] = packed.versions[i];
            slot.bufferOwners[i] = frame.packed;
            uploadedAny = true;
        });
        slot.uploaded = frame.packed;
        if (uploadedAny) uploadSeconds = secondsSince(start);
    }
    const int depth = frame.settings.maxDepth;
    auto found = slot.programs.find(depth);
    if (found == slot.programs.end()) {
        start = Clock::now();
        if (hooks.slowBuildSeconds) std::this_thread::sleep_for(std::chrono::seconds(*hooks.slowBuildSeconds));
        DeviceSlot::Program p;
        p.program = buildKernelProgram(slot.device, slot.context, buildOptions(depth, slot.variant),
                                       [&](const cl::Program& program) {
                                           launchOnNoPixels(slot, program, frame.params, frame.workGroupSize);
                                       });
        p.kernel = cl::Kernel(p.program.program, "renderTile");
        p.privateBytes = p.kernel.getWorkGroupInfo<CL_KERNEL_PRIVATE_MEM_SIZE>(slot.device.device);
        buildSeconds = secondsSince(start);
        found = slot.programs.emplace(depth, std::move(p)).first;
    }
    cl::Kernel& kernel = found->second.kernel;
    // The scene's buffers and the block queue; the launch parameters and the tile outputs are
    // set at each launch.
    for (size_t i = 0; i < kSceneBufferCount; ++i)
        kernel.setArg(kernel_argument::kFirstSceneBuffer + cl_uint(i), slot.sceneBuffers[i]);
    if (slot.variant.lanes > 1) kernel.setArg(kernel_argument::kBlockQueue, slot.blockQueue);
    for (DeviceSlot::TileOutput& out : slot.outputs)
        sizeTileOutput(slot, out, tileEntries(frame.tileWidth, frame.tileHeight, slot.variant.lanes));
    slot.queue.finish();
    std::lock_guard lock(frame.mutex);
    frame.uploadSeconds = std::max(frame.uploadSeconds, uploadSeconds);
    frame.buildSeconds = std::max(frame.buildSeconds, buildSeconds);
    return kernel;
}

// The device's part in one frame: prepare, then render if the frame still wants it. A
// failure drops the device, its tiles going to the others.
void serveFrame(DeviceSlot& slot, Frame& frame) {
    const int index = slot.index;
    try {
        try {
            TestHooks hooks;
            {
                std::lock_guard lock(frame.mutex);
                if (frame.closed) return;  // the device was busy until the frame was over
                hooks = frame.devices[size_t(index)].hooks;
            }
            cl::Kernel& kernel = prepareDevice(slot, frame, hooks);
            {
                std::lock_guard lock(frame.mutex);
                Frame::Participant& p = frame.devices[size_t(index)];
                // Done without it (its program is kept for the next frame), or cancelled.
                if (frame.closed || p.part != Frame::Part::Preparing) return;
                const Clock::time_point now = Clock::now();
                p.part = Frame::Part::Rendering;
                if (!frame.renderingSince) frame.renderingSince = now;
                p.warm = slot.programs.at(frame.settings.maxDepth).warm;
                p.slowestTileSeconds = slot.slowestTileSeconds;
                p.lastAnswer = now;
            }
            DeviceWorker(frame, slot).run(kernel);
        } catch (const cl::Error& err) {
            throw describeClError(slot.device, err);
        }
    } catch (const std::exception& err) {
        {
            std::lock_guard lock(slot.mutex);
            slot.dropped = true;
            slot.failure = err.what();
        }
        std::lock_guard lock(frame.mutex);
        frame.deviceFailed(index);
    }
}

// The device's thread: serves the newest frame posted to it, one after another, until the
// engine stops it or the device is dropped.
void serveFrames(std::shared_ptr<DeviceSlot> slot) {
    uint64_t served = 0;
    while (true) {
        std::shared_ptr<Frame> frame;
        {
            std::unique_lock lock(slot->mutex);
            slot->busy = false;
            slot->wake.wait(lock, [&] { return slot->stop || slot->dropped || slot->frameNumber != served; });
            if (slot->stop || slot->dropped) return;
            frame = slot->frame;
            served = slot->frameNumber;
            slot->busy = true;
        }
        if (frame) serveFrame(*slot, *frame);
    }
}

}  // namespace

struct OpenClEngine::Impl {
    std::shared_ptr<const Scene> scene;        // what the next frame renders
    std::shared_ptr<const Scene> packedScene;  // what `packed` was packed from
    std::vector<OpenClDevice> selection;
    std::vector<std::shared_ptr<DeviceSlot>> slots;
    std::shared_ptr<const PackedScene> packed;
    int packedGridSide = -1;
    bool packedTrilinear = false;
    uint64_t frames = 0;
    uint64_t tableVersions = 0;  // the last version given to a packed table

    Impl(std::shared_ptr<const Scene> s, std::vector<OpenClDevice> d) : scene(std::move(s)), selection(std::move(d)) {}
};

// The caller keeps the scene alive: a shared pointer that does not own it.
OpenClEngine::OpenClEngine(const Scene& scene, std::vector<OpenClDevice> devices)
    : OpenClEngine(std::shared_ptr<const Scene>(&scene, [](const Scene*) {}), std::move(devices)) {}

OpenClEngine::OpenClEngine(std::shared_ptr<const Scene> scene, std::vector<OpenClDevice> devices)
    : impl_(std::make_unique<Impl>(std::move(scene), std::move(devices))) {
    if (impl_->selection.empty()) throw DeviceError("no OpenCL device selected; see ray --list-devices");
    for (const OpenClDevice& d : impl_->selection) {
        auto slot = std::make_shared<DeviceSlot>();
        slot->device = d;
        slot->variant = kernelVariantFor(d, cpuLanesForTests());
        slot->index = int(impl_->slots.size());
        slot->thread = std::thread(serveFrames, slot);
        impl_->slots.push_back(std::move(slot));
    }
}

// Joins the device threads that are idle. A thread still busy (building a kernel, rendering
// the first launch of a frame that was done without it, or hung in the driver) is left to
// finish on its own: it keeps its slot (context, queue, buffers) alive, and a hung one is
// never released, since releasing a hung queue would block too.
OpenClEngine::~OpenClEngine() {
    for (const auto& slot : impl_->slots) {
        bool busy;
        {
            std::lock_guard lock(slot->mutex);
            slot->stop = true;
            slot->frame.reset();
            busy = slot->busy;
        }
        slot->wake.notify_all();
        if (busy)
            slot->thread.detach();
        else
            slot->thread.join();
    }
}

void OpenClEngine::setScene(std::shared_ptr<const Scene> scene) { impl_->scene = std::move(scene); }

const std::vector<OpenClDevice>& OpenClEngine::devices() const { return impl_->selection; }

int OpenClEngine::devicesLeft() const {
    int n = 0;
    for (const auto& s : impl_->slots) {
        std::lock_guard lock(s->mutex);
        n += s->dropped ? 0 : 1;
    }
    return n;
}

namespace {

// Each table's bytes, in the order of PackedScene::forEachBuffer.
std::array<std::pair<const void*, size_t>, kSceneBufferCount> tableBytes(const PackedScene& packed) {
    std::array<std::pair<const void*, size_t>, kSceneBufferCount> bytes;
    size_t next = 0;
    packed.forEachBuffer([&](const auto& table, SceneBufferName) {
        bytes[next++] = {table.data(), table.size() * sizeof(table[0])};
    });
    return bytes;
}

// Packs the scene on the first frame, after a setting that shapes the buffers changed, or
// after the scene changed (setScene): then only what differs from the packed scene is
// packed again when it can be (scene_packing.h repackScene: no BVH build for a material or
// light edit, a refit for moved primitives), and each table that came out the same keeps
// its version, so that the devices keep its buffer.
void packIfNeeded(OpenClEngine::Impl& e, const RenderSettings& settings, FrameStats& stats) {
    const int side = areaLightGridSide(settings);
    const bool tri = settings.textureFilter == TextureFilter::Trilinear;
    const bool sameShape = e.packed && side == e.packedGridSide && tri == e.packedTrilinear;
    if (sameShape && e.packedScene == e.scene) return;
    auto start = Clock::now();
    if (sameShape) {
        SceneDifference difference = compareScenes(*e.packedScene, *e.scene);
        difference.camera = false;  // each frame's camera is its own (renderFrame's)
        if (!difference.any()) {
            e.packedScene = e.scene;
            return;
        }
        if (std::optional<PackedScene> edited = repackScene(*e.packed, *e.scene, settings, difference)) {
            const auto before = tableBytes(*e.packed), after = tableBytes(*edited);
            for (size_t i = 0; i < kSceneBufferCount; ++i) {
                const bool same = before[i].second == after[i].second &&
                                  (before[i].second == 0 ||
                                   std::memcmp(before[i].first, after[i].first, before[i].second) == 0);
                edited->versions[i] = same ? e.packed->versions[i] : ++e.tableVersions;
            }
            stats.packSeconds = secondsSince(start);
            stats.bvhBuildSeconds = 0;
            e.packed = std::make_shared<PackedScene>(std::move(*edited));
            e.packedScene = e.scene;
            return;
        }
    }
    // Idle devices let go of the old tables now (CPU devices read them in place); a busy one
    // keeps them alive until it uploads the new ones.
    e.packed.reset();
    for (const auto& slot : e.slots) {
        std::lock_guard lock(slot->mutex);
        if (!slot->busy) slot->releaseScene();
    }
    start = Clock::now();
    const bool cpuTables = std::any_of(e.slots.begin(), e.slots.end(),
                                       [](const auto& slot) { return slot->variant.cpuThreads; });
    auto fresh = std::make_shared<PackedScene>(packScene(*e.scene, settings, cpuTables));
    for (uint64_t& version : fresh->versions) version = ++e.tableVersions;
    stats.packSeconds = secondsSince(start);
    stats.bvhBuildSeconds = fresh->bvhBuildSeconds;
    e.packed = std::move(fresh);
    e.packedScene = e.scene;
    e.packedGridSide = side;
    e.packedTrilinear = tri;
}

std::string hungMessage(double silentSeconds) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.1f", silentSeconds);
    return "stopped answering: no tile back in " + std::string(seconds) + " s, past its deadline (" +
           std::to_string(int(kDeadlineFactor)) + " times the slowest tile, at least " +
           std::to_string(int(kDeadlineFloorSeconds)) +
           " s); its tiles went to the other devices, and ray does not wait for it";
}

std::string droppedWarning(const DeviceSlot& slot) {
    return "device " + std::to_string(slot.device.index) + " (" + slot.device.description() + ") dropped: " +
           slot.failure;
}

}  // namespace

FrameResult OpenClEngine::renderFrame(const Camera& camera, const RenderSettings& settings, const FrameOptions& options) {
    Impl& e = *impl_;
    FrameResult result;
    FrameStats& stats = result.stats;
    packIfNeeded(e, settings, stats);

    if (options.eightBit)
        result.bytes = ByteImage(settings.width, settings.height);
    else
        result.image = Image(settings.width, settings.height);
    const int side = frameTileSide(settings, *e.scene, options.cancel != nullptr, options.tileSize);
    auto frame = std::make_shared<Frame>();
    frame->options = &options;
    frame->source = options.tiles;
    if (options.tiles)
        frame->scheduler.emplace();
    else
        frame->scheduler.emplace(TileGrid(settings.width, settings.height, side));
    frame->image = options.eightBit ? nullptr : &result.image;
    frame->bytes = options.eightBit ? &result.bytes : nullptr;
    frame->stats = &stats;
    frame->packed = e.packed;
    frame->settings = settings;
    frame->params = makeRenderParams(camera, e.scene->globals, settings, *e.packed);
    frame->tileWidth = std::min(side, settings.width);  // a tile lies within the image
    frame->tileHeight = std::min(side, settings.height);
    frame->workGroupSize = size_t(options.workGroupSize);
    frame->pixelsTotal = uint64_t(settings.width) * uint64_t(settings.height);
    frame->devices.resize(e.slots.size());
    stats.devices.resize(e.slots.size());
    // The index too: two devices of one kind have the same name.
    for (size_t i = 0; i < e.slots.size(); ++i)
        stats.devices[i].device = std::to_string(e.slots[i]->device.index) + ": " + e.slots[i]->device.description();
    if (e.frames == 0)
        for (const OpenClDevice& d : e.selection)
            if (std::string warning = llvmpipeWarning(d); !warning.empty()) stats.warnings.push_back(warning);

    // Each device that is left gets the frame: it starts as soon as its own kernel is built.
    const uint64_t number = ++e.frames;
    const auto renderStart = Clock::now();
    for (size_t i = 0; i < e.slots.size(); ++i) {
        DeviceSlot& slot = *e.slots[i];
        std::lock_guard lock(slot.mutex);
        if (slot.dropped) continue;
        frame->devices[i].part = Frame::Part::Preparing;
        frame->devices[i].hooks = testHooksFor(int(i));
        ++frame->devicesLeft;
        slot.frame = frame;
        slot.frameNumber = number;
        slot.wake.notify_all();
    }

    // Wait for the picture, dropping the devices that stop answering meanwhile.
    {
        std::unique_lock lock(frame->mutex);
        while (!frame->over()) {
            for (const Frame::Silent& hung : frame->dropLateDevices(Clock::now())) {
                DeviceSlot& slot = *e.slots[size_t(hung.device)];
                std::lock_guard slotLock(slot.mutex);
                slot.dropped = slot.hung = true;
                slot.failure = hungMessage(hung.seconds);
            }
            if (frame->over()) break;
            // Wake for the next deadline, and at least every second (a device launching its
            // tiles does not call), or every 50 ms when the frame can be cancelled (the flag is
            // set from another thread, unannounced).
            const Clock::time_point now = Clock::now();
            Clock::time_point wake = now + (options.cancel ? std::chrono::milliseconds(50) : std::chrono::seconds(1));
            if (auto deadline = frame->nextDeadline(now); deadline && *deadline < wake) wake = *deadline;
            frame->changed.wait_until(lock, wake);
        }
        frame->closed = true;
        result.cancelled = frame->cancelled();
        stats.tiles = frame->scheduler->tilesDone();
        stats.uploadSeconds = frame->uploadSeconds;
        stats.kernelBuildSeconds = frame->buildSeconds;
        for (size_t i = 0; i < frame->devices.size(); ++i) {
            stats.devices[i].busySeconds = frame->devices[i].busySeconds;
            stats.devices[i].building = frame->devices[i].part == Frame::Part::Preparing;
        }
        stats.renderSeconds = secondsSince(frame->renderingSince.value_or(renderStart));
    }

    // Every failure is reported once: in this frame, or, for a device that failed after its
    // frame was done (a build that failed late), in the next.
    std::string failures;
    for (size_t i = 0; i < e.slots.size(); ++i) {
        DeviceSlot& slot = *e.slots[i];
        std::lock_guard lock(slot.mutex);
        if (slot.frame == frame) slot.frame.reset();  // a slot keeps no frame that is over
        if (!slot.dropped) continue;
        stats.devices[i].failed = true;
        stats.devices[i].failure = slot.failure;
        failures += (failures.empty() ? "" : "; ") + slot.failure;
        if (slot.failureReported) continue;
        slot.failureReported = true;
        stats.warnings.push_back(droppedWarning(slot));
    }
    if (devicesLeft() == 0) {
        // One device: its own message, as it always was.
        if (e.slots.size() == 1) throw DeviceError(failures);
        throw DeviceError("every OpenCL device failed: " + failures);
    }
    if (!result.cancelled && !frame->allDone())
        throw DeviceError("the frame ended with tiles unrendered");  // a scheduler bug, never silent
    return result;
}

}  // namespace ray
