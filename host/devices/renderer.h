// Choosing the renderers a device string names (auto | cpu | gpu | all | ref | indices) and
// running them: their frame source (makeFrameSource: the viewer's and the API's, frame after
// frame), one frame through it (render, the ray command's), the drivers started early, the
// device list.
//
// The layer above the renderers (reference/, opencl/), below the entry points.
#pragma once

#include <atomic>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <thread>

#include "image/image.h"
#include "render/device_error.h"
#include "render/frame_source.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "scene/scene.h"

namespace ray {

struct RenderJob {
    const Scene& scene;
    const RenderSettings& settings;
    std::string device = "auto";  // auto | cpu | gpu | all | ref | <index> | <index>,<index>...
    std::function<void(double)> progress;
    // Set to true (e.g. from a signal handler) to stop early: the render returns within
    // about a second with RenderedFrame::cancelled set and unrendered pixels black.
    const std::atomic<bool>* cancel = nullptr;
    // The reference renderer tests every primitive for every ray (--no-bvh).
    bool referenceBruteForce = false;
    // OpenCL tile side (--tile-size); 0: automatic (render/tile_side.h frameTileSide).
    int tileSize = 0;
    // Return the image as the 8-bit values an 8-bit file holds (RenderedFrame::bytes), for
    // an output that is one: OpenCL devices keep only those, a quarter of the memory.
    bool eightBit = false;
};


// Whether text is a device selection: auto, cpu, gpu, all, ref (or reference), or a
// device index, or a list of indices such as 0,2.
bool isDeviceSelection(const std::string& text);

// "ref" or "reference": the host reference renderer rather than OpenCL devices.
bool isReferenceDevice(const std::string& device);

// One frame on the devices the job names, through their frame source (makeFrameSource);
// several ("all", a list) cooperate on the frame, tile by tile (opencl/opencl_engine.h).
// Throws DeviceError, InputError.
RenderedFrame render(const RenderJob& job);

// The frame source (render/frame_source.h) for the devices named: the reference renderer
// for ref (testing every primitive for every ray with referenceBruteForce, --no-bvh), else
// the OpenCL engine on the selected devices. Throws DeviceError.
std::unique_ptr<FrameSource> makeFrameSource(const std::string& device, bool referenceBruteForce = false);

// Starts what a render on `device` will need on a thread of its own (the OpenCL drivers;
// nothing for the reference), so that it overlaps the scene's load. The thread is joined
// when the returned object is destroyed.
std::jthread startDeviceEarly(const std::string& device);

// Prints every OpenCL platform and device with its index (--list-devices).
void printDeviceList(std::ostream& out);

// For main, as the process ends: no device's kernel build may run on while exit's handlers
// destroy the drivers' static objects (opencl/opencl_device.h endWithoutPoclBuilds).
// Returns the exit code, or ends the process with it.
int endProcessCleanly(int exitCode);

}  // namespace ray
