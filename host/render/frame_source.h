// One frame of a scene: the one interface every entry point renders through.
//
// Implemented by the two renderers: the reference renderer (reference/reference_frame_source.h,
// rows as tiles, whole frames only) and the OpenCL engine, which packs the scene once and
// renders tiles on the selected devices (opencl/opencl_frame_source.h).
// devices/renderer.h makeFrameSource picks one from a device string.
// Used by every entry point that renders a frame: the ray command (devices/renderer.h
// render), api::Renderer (frame after frame on one source), the viewer (8-bit tiles as they
// come, renderFrame below) and MPI's ranks (tiles admitted from rank 0, FrameRequest::tiles).
// Explain renders no frame: it traces single pixels on the reference renderer.
//
// A frame is: a scene seen by a camera with settings, reported tile by tile as each is
// finished (linear float RGB), stopped early when the request's cancel flag is set, and
// returned whole (floats, or the 8-bit values an 8-bit file holds) with its statistics.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "render/tiles.h"
#include "scene/scene.h"

namespace ray {

// Where a frame's tiles come from when they are not the source's own grid of the image: a
// distributed render admits tiles from rank 0. Called from several threads at once:
// implementations are thread-safe. next() blocks until a tile is available and returns
// false when there are no more for this frame.
class TileSource {
public:
    virtual ~TileSource() = default;
    virtual bool next(TileRect& tile) = 0;
};

// One finished tile: its rectangle, its linear RGB (3 floats a pixel, row by row, width x
// height; valid during the call only), and its rays by kind.
struct FinishedTile {
    TileRect rect;
    const float* rgb = nullptr;
    uint64_t primaryRays = 0, shadowRays = 0, secondaryRays = 0;
    int device = 0;  // position of the device in the source's selection
};

// What a caller asks of one frame besides the scene, camera and settings.
struct FrameRequest {
    // Called for each tile as it is kept (duplicates dropped before), one call at a time,
    // possibly from another thread: for progressive display and distributed renders.
    std::function<void(const FinishedTile&)> onTile;
    // Called with the fraction of the frame done, from render threads.
    std::function<void(double)> progress;
    // Set to true (e.g. from a signal handler) to stop early: the frame comes back within
    // about a second, RenderedFrame::cancelled set, the pixels never rendered black.
    const std::atomic<bool>* cancel = nullptr;
    // Side of the square tiles (--tile-size); 0: render/tile_side.h frameTileSide. With
    // `tiles`, the side of the tiles it admits (for the device limits).
    int tileSize = 0;
    // Where the tiles come from; null: every tile of the image. Only sources that render
    // tiles take it (the reference renderer renders whole frames: DeviceError).
    TileSource* tiles = nullptr;
    // Keep the frame as 8-bit values (RenderedFrame::bytes) instead of floats: on OpenCL
    // devices each tile is quantized as it arrives, a quarter of the memory.
    bool eightBit = false;
};

struct RenderedFrame {
    Image image;      // unless FrameRequest::eightBit (then empty)
    ByteImage bytes;  // with FrameRequest::eightBit (else empty)
    // Rays, timings, the device (and each OpenCL device's share), warnings. The frame's
    // shape (width, height, depth, samples) and the load time are the caller's to add.
    RenderStats stats;
    bool cancelled = false;  // stopped by FrameRequest::cancel: the image is partial
};

// A finished rectangle of the frame, 8-bit RGB as a png would hold it (SPEC §4).
struct FrameTile {
    int x = 0, y = 0, width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

class FrameSource {
public:
    virtual ~FrameSource() = default;
    // Renders `scene` as `camera` sees it. The scene is shared so that a source may keep
    // what it prepared for it between frames (the same pointer: the same scene). Throws
    // DeviceError, InputError.
    virtual RenderedFrame render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                                 const RenderSettings& settings, const FrameRequest& request) = 0;
    // The devices, for a person (the viewer's status line).
    virtual std::string deviceName() const = 0;

    // The viewer's frame: tiles as 8-bit RGB, as it sends them to the page; returns the
    // frame's statistics (its rays, partial when cancelled; what it re-packed).
    RenderStats renderFrame(const std::shared_ptr<const Scene>& scene, const Camera& camera, const RenderSettings& settings,
                         const std::function<void(const FrameTile&)>& onTile, const std::atomic<bool>& cancel);
};

// A shared pointer to a scene the caller owns and keeps alive for the source's life (the
// ray command's one frame): it owns nothing.
std::shared_ptr<const Scene> borrowedScene(const Scene& scene);

}  // namespace ray
