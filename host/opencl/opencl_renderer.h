// One frame on a selection of OpenCL devices, through the engine (opencl_engine.h): the
// command line's path, which renders a single frame.
#pragma once

#include <atomic>
#include <functional>
#include <vector>

#include "image/image.h"
#include "opencl/opencl_device.h"
#include "opencl/opencl_engine.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "scene/scene.h"

namespace ray {

struct OpenClRenderOptions {
    // Side of the square tiles; 0: render/tile_side.h frameTileSide picks it.
    int tileSize = 0;
    // Work-group side. Left to the driver, PoCL picks groups of one work-item, whose
    // per-group overhead dominates; 8×8 suits CPUs and GPUs alike.
    int workGroupSize = 8;
    std::function<void(double)> progress;
    // Set to true to stop early: no more tiles are launched, the ones queued finish, and
    // the image comes back with the tiles never launched black.
    const std::atomic<bool>* cancel = nullptr;
    // Keep the frame as 8-bit values (FrameResult::bytes; FrameOptions::eightBit).
    bool eightBit = false;
};

// Every device of the list cooperates on the frame. Throws DeviceError (build failure,
// device limits, out of memory, every device failed) and InputError. Devices dropped on
// the way are named in stats->warnings.
FrameResult renderOpenClFrame(const std::vector<OpenClDevice>& devices, const Scene& scene,
                              const RenderSettings& settings, const OpenClRenderOptions& options, RenderStats* stats);
// The float image of renderOpenClFrame (options.eightBit is ignored).
Image renderOpenCl(const std::vector<OpenClDevice>& devices, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats);
Image renderOpenCl(const OpenClDevice& device, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats);

}  // namespace ray
