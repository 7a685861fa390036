// One frame of the OpenCL engine (opencl_engine.h) as its threads share it: the engine's
// thread, which opens it, waits for it and closes it, and each device's thread
// (device_thread.h), which prepares for it and renders tiles of it (device_worker.h).
//
// Which device renders which tile is the tile scheduler's (render/tile_scheduler.h), whose
// workers are the devices, by slot index: tiles given back by a failed or hung device first,
// copies of pending tiles at the end of the frame, the first result kept. The frame adds
// what only a device has: its launches in flight, in order, and when it counts as hung
// (frame_deadlines.h).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "core/steady_clock.h"
#include "image/image.h"
#include "opencl/scene_packing.h"
#include "render/frame_source.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "render/tile_scheduler.h"

namespace ray::engine {

using Clock = std::chrono::steady_clock;

// The caller's objects (request, source, image, stats) are touched only under `mutex` while
// the frame is open, or in source->next() while sourceCallers counts it: the engine closes
// the frame before renderFrame returns, and a device thread that was left behind (hung,
// still building) then touches nothing of the caller's.
struct Frame {
    std::mutex mutex;
    std::condition_variable changed;
    bool closed = false;
    int sourceCallers = 0;  // device threads inside source->next()
    const FrameRequest* request = nullptr;
    // Where the tiles come from: null, the scheduler's own grid; else admitted to the
    // scheduler as the source gives them, until it has no more (sourceDone).
    TileSource* source = nullptr;
    bool sourceDone = false;
    std::optional<TileScheduler> scheduler;
    Image* image = nullptr;  // the frame: one of these two (FrameRequest::eightBit)
    ByteImage* bytes = nullptr;
    RenderStats* stats = nullptr;

    // What the devices prepare for; copies, so that a thread left behind may read them.
    std::shared_ptr<const PackedScene> packed;
    RenderSettings settings;
    gpu::RayRenderParams params{};
    int tileWidth = 0, tileHeight = 0;  // a full tile's (a guide: launches grow their buffers as needed)
    size_t tilePixels() const { return size_t(tileWidth) * size_t(tileHeight); }

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
        std::deque<Flight> flights;  // launched and not back, oldest first (they finish in order)
        Clock::time_point lastAnswer;
        bool warm = false;  // a tile came back: its program's launch-time compile is behind it
        double slowestTileSeconds = 0;
        double busySeconds = 0;
    };
    std::vector<Participant> devices;  // by slot index
    int devicesLeft = 0;               // preparing or rendering

    bool cancelled() const { return request->cancel && request->cancel->load(); }
    bool allDone() const { return scheduler->complete(); }

    // The frame can return: its picture is complete (or cancelled) and no device that answers
    // still has a tile in flight, or no device is left. Devices still building, or compiling
    // their first launch, take no part and are not waited for.
    bool over() const;

    // Ends the device's part after a failure; its tiles go to the others.
    void deviceFailed(int index);
};

}  // namespace ray::engine
