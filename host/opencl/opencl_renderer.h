// One frame on OpenCL devices as a float image, through their frame source
// (opencl_frame_source.h): for the tests that compare the kernel's pixels.
#pragma once

#include <vector>

#include "image/image.h"
#include "opencl/opencl_device.h"
#include "render/frame_source.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "scene/scene.h"

namespace ray {

// The tile side, progress and cancel flag of the frame (eightBit and tiles are ignored).
using OpenClRenderOptions = FrameRequest;

// Every device of the list cooperates on the frame. Throws DeviceError (build failure,
// device limits, out of memory, every device failed) and InputError. Devices dropped on
// the way are named in stats->warnings.
Image renderOpenCl(const std::vector<OpenClDevice>& devices, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats);
Image renderOpenCl(const OpenClDevice& device, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats);

}  // namespace ray
