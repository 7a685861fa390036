#include "opencl/opencl_engine.h"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>

#include "opencl/device_slot.h"
#include "opencl/device_thread.h"
#include "opencl/engine_frame.h"
#include "opencl/frame_deadlines.h"
#include "opencl/kernel_build.h"
#include "opencl/kernel_variant.h"
#include "opencl/packed_scene_cache.h"
#include "render/device_error.h"
#include "render/tile_side.h"

namespace ray {

using engine::Clock;
using engine::DeviceSlot;
using engine::Frame;

struct OpenClEngine::Impl {
    engine::PackedSceneCache cache;
    std::vector<OpenClDevice> selection;
    std::vector<std::shared_ptr<DeviceSlot>> slots;
    uint64_t frames = 0;

    Impl(std::shared_ptr<const Scene> s, std::vector<OpenClDevice> d)
        : cache(std::move(s), std::any_of(d.begin(), d.end(),
                                          [](const OpenClDevice& device) { return kernelVariantFor(device).cpuThreads; })),
          selection(std::move(d)) {}
};

// The caller keeps the scene alive: a shared pointer that does not own it.
OpenClEngine::OpenClEngine(const Scene& scene, std::vector<OpenClDevice> devices, const TestHooks& hooks)
    : OpenClEngine(std::shared_ptr<const Scene>(&scene, [](const Scene*) {}), std::move(devices), hooks) {}

OpenClEngine::OpenClEngine(std::shared_ptr<const Scene> scene, std::vector<OpenClDevice> devices,
                           const TestHooks& hooks)
    : impl_(std::make_unique<Impl>(std::move(scene), std::move(devices))) {
    if (impl_->selection.empty()) throw DeviceError("no OpenCL device selected; see ray --list-devices");
    for (const OpenClDevice& d : impl_->selection) {
        auto slot = std::make_shared<DeviceSlot>();
        slot->device = d;
        slot->hooks = hooks;
        slot->variant = kernelVariantFor(d, hooks.cpuPacketLanes);
        slot->index = int(impl_->slots.size());
        slot->thread = std::thread(engine::serveFrames, slot);
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

void OpenClEngine::setScene(std::shared_ptr<const Scene> scene) { impl_->cache.setScene(std::move(scene)); }

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

// The frame the devices are posted: its tiles (the image's grid, or the request's source),
// the packed scene and launch parameters they prepare for, and the result they fill.
std::shared_ptr<Frame> openFrame(OpenClEngine::Impl& e, const Camera& camera, const RenderSettings& settings,
                                 const FrameRequest& request, RenderedFrame& result) {
    if (request.eightBit)
        result.bytes = ByteImage(settings.width, settings.height);
    else
        result.image = Image(settings.width, settings.height);
    const int side = frameTileSide(settings, e.cache.scene(), request.cancel != nullptr, request.tileSize);
    auto frame = std::make_shared<Frame>();
    frame->request = &request;
    frame->source = request.tiles;
    if (request.tiles)
        frame->scheduler.emplace();
    else
        frame->scheduler.emplace(TileGrid(settings.width, settings.height, side));
    frame->image = request.eightBit ? nullptr : &result.image;
    frame->bytes = request.eightBit ? &result.bytes : nullptr;
    frame->stats = &result.stats;
    frame->packed = e.cache.packed();
    frame->settings = settings;
    frame->params = makeRenderParams(camera, e.cache.scene().globals, settings, *frame->packed);
    frame->tileWidth = std::min(side, settings.width);  // a tile lies within the image
    frame->tileHeight = std::min(side, settings.height);
    frame->pixelsTotal = uint64_t(settings.width) * uint64_t(settings.height);
    frame->devices.resize(e.slots.size());
    return frame;
}

// The statistics' names: the selection, and each device with its index (two devices of one
// kind have the same name); on the first frame, the llvmpipe warning.
void nameDevices(const OpenClEngine::Impl& e, RenderStats& stats) {
    for (const OpenClDevice& d : e.selection) stats.device += (stats.device.empty() ? "" : ", ") + d.description();
    stats.devices.resize(e.slots.size());
    for (size_t i = 0; i < e.slots.size(); ++i)
        stats.devices[i].device = std::to_string(e.slots[i]->device.index) + ": " + e.slots[i]->device.description();
    if (e.frames == 0)
        for (const OpenClDevice& d : e.selection)
            if (std::string warning = llvmpipeWarning(d); !warning.empty()) stats.warnings.push_back(warning);
}

// Each device that is left gets the frame: it starts as soon as its own kernel is built.
void postFrame(OpenClEngine::Impl& e, const std::shared_ptr<Frame>& frame) {
    const uint64_t number = ++e.frames;
    for (size_t i = 0; i < e.slots.size(); ++i) {
        DeviceSlot& slot = *e.slots[i];
        std::lock_guard lock(slot.mutex);
        if (slot.dropped) continue;
        frame->devices[i].part = Frame::Part::Preparing;
        ++frame->devicesLeft;
        slot.frame = frame;
        slot.frameNumber = number;
        slot.wake.notify_all();
    }
}

// Waits for the picture, dropping the devices that stop answering meanwhile, then closes the
// frame and takes its statistics.
void awaitFrame(OpenClEngine::Impl& e, Frame& frame, RenderedFrame& result, Clock::time_point renderStart) {
    std::unique_lock lock(frame.mutex);
    while (!frame.over()) {
        for (const engine::SilentDevice& hung : engine::dropLateDevices(frame, Clock::now())) {
            DeviceSlot& slot = *e.slots[size_t(hung.device)];
            std::lock_guard slotLock(slot.mutex);
            slot.dropped = slot.hung = true;
            slot.failure = engine::hungMessage(hung.seconds);
        }
        if (frame.over()) break;
        // Wake for the next deadline, and at least every second (a device launching its
        // tiles does not call), or every 50 ms when the frame can be cancelled (the flag is
        // set from another thread, unannounced).
        const Clock::time_point now = Clock::now();
        Clock::time_point wake =
            now + (frame.request->cancel ? std::chrono::milliseconds(50) : std::chrono::seconds(1));
        if (auto deadline = engine::nextDeadline(frame, now); deadline && *deadline < wake) wake = *deadline;
        frame.changed.wait_until(lock, wake);
    }
    frame.closed = true;
    result.cancelled = frame.cancelled();
    RenderStats& stats = result.stats;
    stats.uploadSeconds = frame.uploadSeconds;
    stats.kernelBuildSeconds = frame.buildSeconds;
    for (size_t i = 0; i < frame.devices.size(); ++i) {
        stats.devices[i].busySeconds = frame.devices[i].busySeconds;
        stats.devices[i].building = frame.devices[i].part == Frame::Part::Preparing;
    }
    stats.renderSeconds = secondsSince(frame.renderingSince.value_or(renderStart));
}

std::string droppedWarning(const DeviceSlot& slot) {
    return "device " + std::to_string(slot.device.index) + " (" + slot.device.description() + ") dropped: " +
           slot.failure;
}

// Every failure is reported once: in this frame, or, for a device that failed after its
// frame was done (a build that failed late), in the next. Returns the failures of the
// devices dropped so far, "; " between them.
std::string reportFailures(OpenClEngine::Impl& e, const std::shared_ptr<Frame>& frame, RenderStats& stats) {
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
    return failures;
}

}  // namespace

RenderedFrame OpenClEngine::renderFrame(const Camera& camera, const RenderSettings& settings,
                                        const FrameRequest& request) {
    Impl& e = *impl_;
    RenderedFrame result;
    e.cache.update(settings, result.stats, [&] {
        for (const auto& slot : e.slots) {
            std::lock_guard lock(slot->mutex);
            if (!slot->busy) slot->releaseScene();
        }
    });
    const std::shared_ptr<Frame> frame = openFrame(e, camera, settings, request, result);
    nameDevices(e, result.stats);
    const auto renderStart = Clock::now();
    postFrame(e, frame);
    awaitFrame(e, *frame, result, renderStart);
    const std::string failures = reportFailures(e, frame, result.stats);
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
