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
//
// The parts, each a file of host/opencl/: this class posts each frame to the devices, waits
// for it and reports it; packed_scene_cache (packing and re-packing after edits),
// engine_frame (one frame as the threads share it), frame_deadlines (when a device is hung),
// device_slot (what a device keeps between frames), device_thread (a device's thread: each
// frame prepared for), scene_upload (device limits and uploads), kernel_build (build options,
// packet width, the program built and run once), device_worker (a device's tiles in flight).
#pragma once

#include <memory>
#include <vector>

#include "core/test_hooks.h"
#include "opencl/opencl_device.h"
#include "render/frame_source.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace ray {

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

    // Renders one frame from the camera with the settings, as the request asks
    // (render/frame_source.h; the callbacks are called from device threads, one call at a
    // time; a cancelled frame launches no more tiles and lets those queued finish). The
    // statistics hold the rays, each device's share, and the seconds of what this frame did:
    // packing and BVH build (0 unless it packed), the slowest device's upload (0 unless it
    // uploaded) and kernel build (0 when every program was kept), and the render; the
    // warnings, each device dropped (once) and llvmpipe on the first frame. Devices dropped
    // in a frame stay dropped. Throws DeviceError when no device is left (or the scene does
    // not fit any), InputError for bad settings.
    RenderedFrame renderFrame(const Camera& camera, const RenderSettings& settings, const FrameRequest& request = {});

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
