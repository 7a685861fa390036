#include "opencl/opencl_engine.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/memory_limits.h"
#include "opencl/scene_packing.h"
#include "render/renderer.h"

namespace ray {

namespace {

using Clock = std::chrono::steady_clock;

constexpr size_t kTilesInFlight = 4;  // per device: it never idles between launches
// renderTile's arguments for the launch's tile outputs (cl/render.cl).
constexpr cl_uint kColorsArgument = 7, kCountsArgument = 8;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string mebibytes(uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

// Refuses, before any upload, a scene whose buffers exceed what the device allows.
void checkDeviceLimits(const OpenClDevice& device, const PackedScene& packed, size_t tileBytes) {
    struct Buffer {
        const char* what;
        size_t bytes;
    };
    const Buffer buffers[] = {{"BVH nodes", packed.nodes.size() * sizeof(gpu::RayWideBvhNode)},
                              {"primitives", packed.primitives.size() * sizeof(gpu::RayPrimitive)},
                              {"textures", packed.texels.size()},
                              {"mesh triangles", packed.triangleShading.size() * sizeof(gpu::RayTriangleShading)},
                              {"tile", tileBytes}};
    const std::string advice = "; use a smaller scene or image, another device (ray --list-devices), or --device ref";
    for (const Buffer& b : buffers) {
        if (b.bytes > device.maxAllocation)
            throw DeviceError("the scene's " + std::string(b.what) + " need a " + mebibytes(b.bytes) +
                              " buffer, more than the " + mebibytes(device.maxAllocation) + " " +
                              device.description() + " allows in one allocation" + advice);
    }
    // Each launch in flight has its colors and ray counts: two buffers of tileBytes.
    uint64_t total = packed.totalBytes() + 2 * kTilesInFlight * uint64_t(tileBytes);
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

// A test hook: RAY_TEST_BVH_SHORT_STACK=N builds the kernel with an N-entry traversal
// stack (cl/intersect.cl BvhStack), so that tests can make every walk overflow and show
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

std::string buildOptions(int maxDepth) {
    // One frame per bounce plus the camera ray (cl/render.cl). No -cl-fast-relaxed-math:
    // the intersection code relies on IEEE infinities.
    return "-cl-std=CL1.2 -DRAY_MAX_FRAMES=" + std::to_string(maxDepth + 1) + shortStackOption();
}

DeviceError describeClError(const OpenClDevice& device, const cl::Error& e) {
    std::string what = openClErrorName(e.err());
    std::string advice = (e.err() == CL_MEM_OBJECT_ALLOCATION_FAILURE || e.err() == CL_OUT_OF_RESOURCES ||
                          e.err() == CL_OUT_OF_HOST_MEMORY)
                             ? "the device ran out of memory; try a smaller image or scene, or --device ref"
                             : "try another device (ray --list-devices) or --device ref";
    return DeviceError(device.description() + ": " + e.what() + " failed with " + what + "; " + advice);
}

// RAY_TEST_FAIL_DEVICE="k:n": device k of the selection fails after n tiles of a frame.
std::optional<int> testFailureAfter(int deviceSlot) {
    const char* hook = std::getenv("RAY_TEST_FAIL_DEVICE");
    if (!hook) return std::nullopt;
    int k = -1, n = -1;
    if (std::sscanf(hook, "%d:%d", &k, &n) != 2 || k != deviceSlot || n < 0) return std::nullopt;
    return n;
}

// The engine's own tile source: the image cut into a grid of square tiles, row by row.
class GridTiles : public TileSource {
public:
    GridTiles(int width, int height, int side) : grid_(width, height, side) {}
    bool next(TileRect& tile) override {
        std::lock_guard lock(mutex_);
        if (nextIndex_ >= grid_.count()) return false;
        tile = grid_.tile(nextIndex_++);
        return true;
    }

private:
    std::mutex mutex_;
    TileGrid grid_;
    int nextIndex_ = 0;
};

// A tile of a frame as the scheduler sees it.
enum class TileState { Queued, InFlight, Done };

}  // namespace

// What one device keeps between frames: its context, queue, uploaded scene, programs.
struct DeviceSlot {
    OpenClDevice device;
    bool dropped = false;
    cl::Context context;
    cl::CommandQueue queue;
    int uploadedVersion = -1;  // the engine's packVersion these buffers hold
    size_t checkedTilePixels = 0;  // the tile size checkDeviceLimits last passed with them
    cl::Buffer nodes, primitives, materials, lights, textures, texels, triangles, triangleShading, motions;
    // Lets go of the scene's buffers: before the packed tables they may use in place change.
    void releaseScene() {
        nodes = primitives = materials = lights = textures = texels = triangles = triangleShading = motions = {};
        uploadedVersion = -1;
    }
    // Launch k writes its tile into outputs[k % kTilesInFlight]: tile-sized buffers, so a
    // frame costs the device (and, on a CPU device, the host) a few tiles, not two
    // full-frame copies of the image (32 bytes a pixel: 25 MB at 1024x768, 265 MB at 4K).
    struct TileOutput {
        cl::Buffer colors, counts;
        size_t pixels = 0;
    };
    std::array<TileOutput, kTilesInFlight> outputs;
    struct Program {
        KernelProgram program;
        cl::Kernel kernel;
    };
    std::map<int, Program> programs;  // by maximum depth
};

struct OpenClEngine::Impl {
    const Scene& scene;
    std::vector<OpenClDevice> selection;
    std::vector<std::unique_ptr<DeviceSlot>> slots;
    PackedScene packed;
    int packVersion = 0;
    bool packed_ = false;
    int packedGridSide = -1;
    bool packedTrilinear = false;

    Impl(const Scene& s, std::vector<OpenClDevice> d) : scene(s), selection(std::move(d)) {}
};

namespace {

// The state of one frame shared by the device threads.
struct Frame {
    std::mutex mutex;
    std::condition_variable changed;
    const FrameOptions* options = nullptr;
    TileSource* source = nullptr;
    std::vector<TileRect> tiles;
    std::vector<TileState> state;
    std::vector<int> flights;  // devices rendering each tile now
    std::deque<int> queue;     // tiles put back by a failed device
    bool sourceDone = false;
    int done = 0, devicesLeft = 0;
    int preparing = 0;  // devices still uploading or building: tiles wait for all of them
    uint64_t pixelsDone = 0, pixelsTotal = 0;
    Image* image = nullptr;     // the frame: one of these two (FrameOptions::eightBit)
    ByteImage* bytes = nullptr;
    FrameStats* stats = nullptr;

    bool cancelled() const { return options->cancel && options->cancel->load(); }
    // The first tiles wait until every device has its scene and program: a device whose
    // cached kernel loads first would otherwise take a small frame's every tile.
    void deviceReady() {
        std::lock_guard lock(mutex);
        --preparing;
        changed.notify_all();
    }
    void waitForEveryDevice() {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return preparing == 0; });
    }
    bool allDone() const { return sourceDone && queue.empty() && done == int(tiles.size()); }
};

// One device's part of a frame, run on its own host thread.
class DeviceWorker {
public:
    DeviceWorker(Frame& frame, DeviceSlot& slot, int slotIndex, const gpu::RayRenderParams& params)
        : frame_(frame), slot_(slot), index_(slotIndex), params_(params), failAfter_(testFailureAfter(slotIndex)) {}

    void run(cl::Kernel& kernel) {
        auto start = Clock::now();
        bool started = false;
        while (true) {
            if (failAfter_ && finished_ >= *failAfter_)
                throw DeviceError(slot_.device.description() + ": failed on purpose (RAY_TEST_FAIL_DEVICE)");
            while (inFlight_.size() < kTilesInFlight) {
                std::optional<int> tile = acquire();
                if (!tile) break;
                if (!started) start = Clock::now(), started = true;
                launch(kernel, *tile);
            }
            if (inFlight_.empty()) {
                std::unique_lock lock(frame_.mutex);
                if (frame_.cancelled() || frame_.allDone()) break;
                frame_.changed.wait_for(lock, std::chrono::milliseconds(50));
                continue;
            }
            finishOldest();
            busySeconds_ = secondsSince(start);
        }
        std::lock_guard lock(frame_.mutex);
        frame_.stats->devices[size_t(index_)].busySeconds = busySeconds_;
    }

    // Puts every tile this device still holds back in the queue.
    void abandonTiles() {
        std::lock_guard lock(frame_.mutex);
        for (const Launch& l : inFlight_) {
            if (frame_.state[size_t(l.tile)] == TileState::Done) continue;
            if (--frame_.flights[size_t(l.tile)] == 0) {
                frame_.state[size_t(l.tile)] = TileState::Queued;
                frame_.queue.push_back(l.tile);
            }
        }
        inFlight_.clear();
        frame_.stats->devices[size_t(index_)].busySeconds = busySeconds_;
    }

private:
    struct Launch {
        int tile;
        size_t output;  // index in slot_.outputs
        cl::Event event;
    };

    // The next tile for this device: one put back, else a new one from the source, else
    // (when this device is idle) one still pending on another device.
    std::optional<int> acquire() {
        std::unique_lock lock(frame_.mutex);
        if (frame_.cancelled()) return std::nullopt;
        if (!frame_.queue.empty()) return take(frame_.queue.front(), true);
        if (!frame_.sourceDone) {
            lock.unlock();
            TileRect rect;
            bool more = frame_.source->next(rect);  // may block (a distributed source)
            lock.lock();
            if (more) {
                frame_.tiles.push_back(rect);
                frame_.state.push_back(TileState::Queued);
                frame_.flights.push_back(0);
                return take(int(frame_.tiles.size()) - 1, false);
            }
            frame_.sourceDone = true;
            if (!frame_.queue.empty()) return take(frame_.queue.front(), true);
        }
        if (!inFlight_.empty()) return std::nullopt;
        // End of the frame: duplicate the pending tile with the fewest devices on it.
        int best = -1;
        for (size_t t = 0; t < frame_.tiles.size(); ++t)
            if (frame_.state[t] == TileState::InFlight && (best < 0 || frame_.flights[t] < frame_.flights[size_t(best)]))
                best = int(t);
        if (best < 0) return std::nullopt;
        return take(best, false);
    }

    int take(int tile, bool fromQueue) {
        if (fromQueue) frame_.queue.pop_front();
        frame_.state[size_t(tile)] = TileState::InFlight;
        ++frame_.flights[size_t(tile)];
        return tile;
    }

    void launch(cl::Kernel& kernel, int tile) {
        TileRect rect;
        {
            std::lock_guard lock(frame_.mutex);
            rect = frame_.tiles[size_t(tile)];
        }
        const size_t group = size_t(frame_.options->workGroupSize);
        auto roundUp = [group](int n) { return (size_t(n) + group - 1) / group * group; };
        gpu::RayRenderParams params = params_;
        params.image.z = rect.x;
        params.image.w = rect.y;
        params.tile = {rect.width, rect.height, 0, 0};
        // At most kTilesInFlight launches, finished in order: this output's last user is done.
        const size_t output = launches_++ % kTilesInFlight;
        DeviceSlot::TileOutput& out = slot_.outputs[output];
        const size_t pixels = size_t(rect.width) * size_t(rect.height);
        if (out.pixels < pixels) {
            // Host-allocatable: zero-copy reads on CPU devices (PoCL).
            out.colors = cl::Buffer(slot_.context, CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR, pixels * sizeof(cl_float4));
            out.counts = cl::Buffer(slot_.context, CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR, pixels * sizeof(cl_uint4));
            out.pixels = pixels;
        }
        // Arguments are captured at enqueue time.
        kernel.setArg(0, sizeof(params), &params);
        kernel.setArg(kColorsArgument, out.colors);
        kernel.setArg(kCountsArgument, out.counts);
        Launch l{tile, output, {}};
        slot_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(roundUp(rect.width), roundUp(rect.height)),
                                         cl::NDRange(group, group), nullptr, &l.event);
        slot_.queue.flush();
        inFlight_.push_back(l);
    }

    // Waits for the oldest launch, reads its tile back and keeps it unless another device
    // finished it first.
    void finishOldest() {
        Launch l = inFlight_.front();
        l.event.wait();
        TileRect rect;
        {
            std::lock_guard lock(frame_.mutex);
            rect = frame_.tiles[size_t(l.tile)];
        }
        const size_t n = size_t(rect.width) * size_t(rect.height);
        std::vector<cl_float4> rgba(n);
        std::vector<cl_uint4> rays(n);
        const DeviceSlot::TileOutput& out = slot_.outputs[l.output];
        slot_.queue.enqueueReadBuffer(out.colors, CL_TRUE, 0, n * sizeof(cl_float4), rgba.data());
        slot_.queue.enqueueReadBuffer(out.counts, CL_TRUE, 0, n * sizeof(cl_uint4), rays.data());
        inFlight_.pop_front();

        FinishedTile result;
        result.rect = rect;
        result.device = index_;
        std::vector<float> rgb(n * 3);
        for (size_t p = 0; p < n; ++p) {
            for (int c = 0; c < 3; ++c) rgb[p * 3 + size_t(c)] = rgba[p].s[c];
            result.primaryRays += rays[p].s[0];
            result.shadowRays += rays[p].s[1];
            result.secondaryRays += rays[p].s[2];
        }
        result.rgb = rgb.data();
        keep(l.tile, result);
    }

    void keep(int tile, const FinishedTile& result) {
        std::lock_guard lock(frame_.mutex);
        --frame_.flights[size_t(tile)];
        if (frame_.state[size_t(tile)] == TileState::Done) {
            ++frame_.stats->duplicatesDropped;
            return;
        }
        frame_.state[size_t(tile)] = TileState::Done;
        ++frame_.done;
        ++finished_;
        const TileRect& r = result.rect;
        if (frame_.bytes)
            pasteTile(*frame_.bytes, r, result.rgb);
        else
            pasteTile(*frame_.image, r, result.rgb);
        FrameStats& s = *frame_.stats;
        s.primaryRays += result.primaryRays;
        s.shadowRays += result.shadowRays;
        s.secondaryRays += result.secondaryRays;
        DeviceStats& d = s.devices[size_t(index_)];
        ++d.tiles;
        d.pixels += uint64_t(r.width) * uint64_t(r.height);
        d.rays += result.primaryRays + result.shadowRays + result.secondaryRays;
        frame_.pixelsDone += uint64_t(r.width) * uint64_t(r.height);
        if (frame_.options->onTile) frame_.options->onTile(result);
        if (frame_.options->progress && frame_.pixelsTotal > 0)
            frame_.options->progress(std::min(1.0, double(frame_.pixelsDone) / double(frame_.pixelsTotal)));
        frame_.changed.notify_all();
    }

    Frame& frame_;
    DeviceSlot& slot_;
    int index_;
    gpu::RayRenderParams params_;
    std::optional<int> failAfter_;
    std::deque<Launch> inFlight_;
    size_t launches_ = 0;
    int finished_ = 0;
    double busySeconds_ = 0;
};

}  // namespace

OpenClEngine::OpenClEngine(const Scene& scene, std::vector<OpenClDevice> devices)
    : impl_(std::make_unique<Impl>(scene, std::move(devices))) {
    if (impl_->selection.empty()) throw DeviceError("no OpenCL device selected; see ray --list-devices");
    for (const OpenClDevice& d : impl_->selection) {
        auto slot = std::make_unique<DeviceSlot>();
        slot->device = d;
        impl_->slots.push_back(std::move(slot));
    }
}

OpenClEngine::~OpenClEngine() = default;

const std::vector<OpenClDevice>& OpenClEngine::devices() const { return impl_->selection; }

int OpenClEngine::devicesLeft() const {
    int n = 0;
    for (const auto& s : impl_->slots) n += s->dropped ? 0 : 1;
    return n;
}

namespace {

// Uploads the scene (when the device holds an older packing), sizes the output buffers,
// builds (or reuses) the program for the frame's depth and binds the buffers.
cl::Kernel& prepareDevice(DeviceSlot& slot, const PackedScene& packed, int packVersion, const RenderSettings& settings,
                          size_t tilePixels, double& uploadSeconds, double& buildSeconds) {
    if (slot.uploadedVersion != packVersion || slot.checkedTilePixels != tilePixels) {
        checkDeviceLimits(slot.device, packed, tilePixels * sizeof(cl_float4));
        slot.checkedTilePixels = tilePixels;
    }
    if (!slot.context()) {
        slot.context = cl::Context(slot.device.device);
        slot.queue = cl::CommandQueue(slot.context, slot.device.device);
    }
    auto start = Clock::now();
    if (slot.uploadedVersion != packVersion) {
        const bool inPlace = slot.device.isCpu;
        slot.nodes = uploadBuffer(slot.context, packed.nodes, inPlace);
        slot.primitives = uploadBuffer(slot.context, packed.primitives, inPlace);
        slot.materials = uploadBuffer(slot.context, packed.materials, inPlace);
        slot.lights = uploadBuffer(slot.context, packed.lights, inPlace);
        slot.textures = uploadBuffer(slot.context, packed.textures, inPlace);
        slot.texels = uploadBuffer(slot.context, packed.texels, inPlace);
        slot.triangles = uploadBuffer(slot.context, packed.triangles, inPlace);
        slot.triangleShading = uploadBuffer(slot.context, packed.triangleShading, inPlace);
        slot.motions = uploadBuffer(slot.context, packed.motions, inPlace);  // one placeholder when nothing moves
        slot.uploadedVersion = packVersion;
        uploadSeconds = secondsSince(start);
    }
    auto found = slot.programs.find(settings.maxDepth);
    if (found == slot.programs.end()) {
        DeviceSlot::Program p;
        p.program = buildKernelProgram(slot.device, slot.context, buildOptions(settings.maxDepth));
        p.kernel = cl::Kernel(p.program.program, "renderTile");
        buildSeconds = p.program.buildSeconds;
        found = slot.programs.emplace(settings.maxDepth, std::move(p)).first;
    }
    cl::Kernel& kernel = found->second.kernel;
    // Arguments 1-11 in renderTile's order; the tile outputs are set at each launch.
    const std::pair<cl_uint, const cl::Buffer*> args[] = {
        {1, &slot.nodes},     {2, &slot.primitives}, {3, &slot.materials}, {4, &slot.lights},
        {5, &slot.textures},  {6, &slot.texels},     {9, &slot.triangles}, {10, &slot.triangleShading},
        {11, &slot.motions}};
    for (const auto& [index, buffer] : args) kernel.setArg(index, *buffer);
    return kernel;
}

}  // namespace

FrameResult OpenClEngine::renderFrame(const Camera& camera, const RenderSettings& settings, const FrameOptions& options) {
    Impl& e = *impl_;
    FrameResult result;
    FrameStats& stats = result.stats;
    // Repack only when a setting that shapes the buffers changed.
    const int gridSide = areaLightGridSide(settings);
    const bool trilinear = settings.textureFilter == TextureFilter::Trilinear;
    if (!e.packed_ || gridSide != e.packedGridSide || trilinear != e.packedTrilinear) {
        for (const auto& slot : e.slots) slot->releaseScene();  // they may read the old tables in place
        auto start = Clock::now();
        e.packed = packScene(e.scene, settings);
        stats.packSeconds = secondsSince(start);
        stats.bvhBuildSeconds = e.packed.bvhBuildSeconds;
        e.packed_ = true;
        e.packedGridSide = gridSide;
        e.packedTrilinear = trilinear;
        ++e.packVersion;
    }
    const gpu::RayRenderParams params = makeRenderParams(camera, e.scene.globals, settings, e.packed);

    if (options.eightBit)
        result.bytes = ByteImage(settings.width, settings.height);
    else
        result.image = Image(settings.width, settings.height);
    const int side = std::max(8, options.tileSize > 0 ? options.tileSize : 128);
    GridTiles grid(settings.width, settings.height, side);
    const size_t tilePixels = size_t(side) * size_t(side);  // a guide: launches grow their buffers as needed
    Frame frame;
    frame.options = &options;
    frame.source = options.tiles ? options.tiles : &grid;
    frame.image = options.eightBit ? nullptr : &result.image;
    frame.bytes = options.eightBit ? &result.bytes : nullptr;
    frame.stats = &stats;
    frame.pixelsTotal = uint64_t(settings.width) * uint64_t(settings.height);
    stats.devices.resize(e.slots.size());
    // The index too: two devices of one kind have the same name.
    for (size_t i = 0; i < e.slots.size(); ++i)
        stats.devices[i].device = std::to_string(e.slots[i]->device.index) + ": " + e.slots[i]->device.description();

    std::vector<std::string> failures(e.slots.size());
    std::vector<double> uploads(e.slots.size(), 0), builds(e.slots.size(), 0);
    for (const auto& slot : e.slots) frame.devicesLeft += slot->dropped ? 0 : 1;
    frame.preparing = frame.devicesLeft;
    auto renderStart = Clock::now();
    std::vector<std::thread> threads;
    for (size_t i = 0; i < e.slots.size(); ++i) {
        DeviceSlot& slot = *e.slots[i];
        if (slot.dropped) continue;
        threads.emplace_back([&, i] {
            DeviceSlot& s = *e.slots[i];
            DeviceWorker worker(frame, s, int(i), params);
            try {
                try {
                    cl::Kernel* kernel = nullptr;
                    try {
                        kernel = &prepareDevice(s, e.packed, e.packVersion, settings, tilePixels, uploads[i],
                                                builds[i]);
                    } catch (...) {
                        frame.deviceReady();
                        throw;
                    }
                    frame.deviceReady();
                    frame.waitForEveryDevice();
                    worker.run(*kernel);
                } catch (const cl::Error& err) {
                    throw describeClError(s.device, err);
                }
            } catch (const std::exception& err) {
                worker.abandonTiles();
                std::lock_guard lock(frame.mutex);
                failures[i] = err.what();
                s.dropped = true;
                stats.devices[i].failed = true;
                stats.devices[i].failure = err.what();
                --frame.devicesLeft;
                frame.changed.notify_all();
            }
        });
    }
    for (std::thread& t : threads) t.join();
    stats.renderSeconds = secondsSince(renderStart);
    stats.uploadSeconds = *std::max_element(uploads.begin(), uploads.end());
    stats.kernelBuildSeconds = *std::max_element(builds.begin(), builds.end());
    stats.tiles = frame.done;
    result.cancelled = frame.cancelled();

    std::string allFailures;
    for (size_t i = 0; i < failures.size(); ++i) {
        if (failures[i].empty()) continue;
        stats.warnings.push_back("device " + std::to_string(e.slots[i]->device.index) + " (" + e.slots[i]->device.description() + ")" + " dropped: " + failures[i]);
        allFailures += (allFailures.empty() ? "" : "; ") + failures[i];
    }
    if (frame.devicesLeft == 0) {
        // One device: its own message, as it always was.
        if (e.slots.size() == 1) throw DeviceError(allFailures);
        throw DeviceError("every OpenCL device failed: " + allFailures);
    }
    if (!result.cancelled && !frame.allDone())
        throw DeviceError("the frame ended with tiles unrendered");  // a scheduler bug, never silent
    return result;
}

}  // namespace ray
