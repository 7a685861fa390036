// The persistent OpenCL engine: one Scene, packed once and uploaded once to each device of
// a selection, then rendered frame after frame, every device of the selection cooperating
// on each frame.
//
// Per frame: a camera and RenderSettings. The packed buffers (BVH, primitives, materials,
// lights, textures, meshes, motions) depend only on the scene and on two settings that
// shape them (the area lights' sample grid and trilinear mipmaps): they are packed and
// uploaded on the first frame and again only when one of those two changes. The kernel is
// built per device for each maximum depth (a build option) and kept. Everything else (the
// camera, image size, antialiasing, features, seed, shutter) is the kernel's per-launch
// parameter block and costs nothing to change.
//
// Scheduling: one host thread per device, kept for the engine's life, each with its own
// context, queue, program and buffers. Each device starts on a frame as soon as its own scene
// is uploaded and its own kernel built: a slow first build (a GPU driver's can take minutes)
// holds back no other device. A device still building when the frame is done takes no part
// in it and keeps building, for the next frame. The devices are the workers of one tile
// scheduler (render/tile_scheduler.h, the same that hands a distributed render's tiles to
// its ranks); each device keeps a few tiles in flight. When no tile is left to hand out, an
// idle device renders again a tile still pending on another; the first result wins and the
// duplicate is dropped. Every pixel is a
// pure function of its coordinates and the seed, so the image does not depend on which
// device rendered a tile. A device that fails has its tiles put back in the queue and is
// dropped with a warning naming it; the frame fails (DeviceError) only when no device is left.
//
// Hung devices: a device with tiles in flight that sends none back within its deadline (10
// times the slowest tile of the frame, at least 10 s; a device's first tile with a program,
// which PoCL also compiles for the launch, gets 300 s) is taken for hung while another device
// still answers: its tiles go back to the queue (the first result wins, its own if it answers
// late after all), it is dropped with a warning and gets no more tiles. The frame waits for
// the devices that answer to bring back their tiles in flight, but not for a hung device nor
// one still building or compiling its first launch. When every device is late at once, the
// machine stalled (a suspend): none is dropped. A hung OpenCL queue can neither be finished
// nor released, so the engine's destructor does not wait for the thread of such a device (nor
// for one still building): the thread is left, with its context and queue, and the process
// exits without it.
//
// Test hooks (core/test_hooks.h) make a device fail, hang (its launches after the first n
// wait for an OpenCL user event that is never set, so that its thread blocks in the driver as
// on a hung GPU) or build slowly, and choose its kernel's packet width and stack.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/test_hooks.h"
#include "image/image.h"
#include "opencl/opencl_device.h"
#include "render/frame_source.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "render/tiles.h"
#include "scene/scene.h"

namespace ray {

// TileSource (tiles admitted from elsewhere) and FinishedTile: render/frame_source.h.

struct FrameOptions {
    // Side of the square tiles; 0: render/tile_side.h frameTileSide picks it (smaller when the
    // frame can be cancelled). With `tiles`, the side of the tiles it gives (for the
    // device limits: a launch grows its buffers to the tile it gets).
    int tileSize = 0;
    // Work-group side: PoCL left alone picks groups of one work-item; 8x8 suits CPUs and GPUs.
    int workGroupSize = 8;
    // Called with the fraction of the frame done, from device threads, one call at a time.
    std::function<void(double)> progress;
    // Called for each tile as it is kept (duplicates are dropped before), one call at a
    // time, from device threads: for progressive display and distributed renders.
    std::function<void(const FinishedTile&)> onTile;
    // Set to true to stop early: no more tiles are launched, the ones queued finish, and
    // the image comes back with the tiles never rendered black.
    const std::atomic<bool>* cancel = nullptr;
    // Where the tiles come from; null: every tile of the image, cut by tileSize.
    TileSource* tiles = nullptr;
    // Keep the frame as the 8-bit values an 8-bit file holds (FrameResult::bytes), each
    // tile quantized as it arrives, instead of floats: a quarter of the memory.
    bool eightBit = false;
};

struct FrameStats {
    uint64_t primaryRays = 0, shadowRays = 0, secondaryRays = 0;
    double packSeconds = 0;    // packing and BVH build: 0 unless the frame (re)packed
    double bvhBuildSeconds = 0;
    double uploadSeconds = 0;  // slowest device's upload: 0 unless the frame uploaded
    double kernelBuildSeconds = 0;  // slowest device's build: 0 when every program was kept
    double renderSeconds = 0;
    int tiles = 0, duplicatesDropped = 0;
    std::vector<DeviceStats> devices;
    std::vector<std::string> warnings;  // one per device dropped (once), and llvmpipe on the first frame
};

struct FrameResult {
    Image image;      // the frame, unless FrameOptions::eightBit (then empty)
    ByteImage bytes;  // the frame with FrameOptions::eightBit (else empty)
    FrameStats stats;
    bool cancelled = false;
};

class OpenClEngine {
public:
    // Keeps a reference to the scene, which must outlive the engine. Nothing is packed,
    // built or uploaded until the first frame. Throws DeviceError for an empty selection.
    OpenClEngine(const Scene& scene, std::vector<OpenClDevice> devices, const TestHooks& hooks = testHooks());
    // The same, owning a share of the scene.
    OpenClEngine(std::shared_ptr<const Scene> scene, std::vector<OpenClDevice> devices,
                 const TestHooks& hooks = testHooks());
    ~OpenClEngine();
    OpenClEngine(const OpenClEngine&) = delete;
    OpenClEngine& operator=(const OpenClEngine&) = delete;

    // Renders one frame from the camera with the settings. Devices dropped in a frame
    // stay dropped. Throws DeviceError when no device is left (or the scene does not fit
    // any), InputError for bad settings.
    FrameResult renderFrame(const Camera& camera, const RenderSettings& settings, const FrameOptions& options = {});

    // The scene of the next frames: an edited copy of the one before (an editor's). The
    // next frame packs and uploads only what differs from the scene it packed (a material
    // or light edit: its table; moved primitives: their records and a refitted tree; no BVH
    // build for either), and a whole packing for anything else.
    void setScene(std::shared_ptr<const Scene> scene);

    const std::vector<OpenClDevice>& devices() const;
    int devicesLeft() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace ray
