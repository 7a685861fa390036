// The fast path: renders a packed scene with the OpenCL kernel, tile by tile.
#pragma once

#include <atomic>
#include <functional>

#include "image/image.h"
#include "opencl/opencl_device.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "scene/scene.h"

namespace ray {

struct OpenClRenderOptions {
    // Side of the square tiles launched one at a time: short launches keep GPU watchdogs
    // quiet and let the progress bar move.
    int tileSize = 128;
    // Work-group side. Left to the driver, PoCL picks groups of one work-item, whose
    // per-group overhead dominates; 8×8 suits CPUs and GPUs alike.
    int workGroupSize = 8;
    std::function<void(double)> progress;
    // Set to true to stop early: no more tiles are launched, the ones queued finish, and
    // the image comes back with the tiles never launched black.
    const std::atomic<bool>* cancel = nullptr;
};

// Throws DeviceError (build failure, device limits, out of memory) and InputError.
Image renderOpenCl(const OpenClDevice& device, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats);

}  // namespace ray
