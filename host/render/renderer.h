// Choosing a renderer (an OpenCL device or the host reference) and running it.
#pragma once

#include <atomic>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <thread>

#include "image/image.h"
#include "render/device_error.h"
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
    // about a second with RenderOutput::interrupted set and unrendered pixels black.
    const std::atomic<bool>* cancel = nullptr;
    // The reference renderer tests every primitive for every ray (--no-bvh).
    bool referenceBruteForce = false;
    // OpenCL tile side (--tile-size); 0: automatic.
    int tileSize = 0;
    // Return the image as the 8-bit values an 8-bit file holds (RenderOutput::bytes), for
    // an output that is one: OpenCL devices keep only those, a quarter of the memory.
    bool eightBit = false;
};

struct RenderOutput {
    Image image;      // unless RenderJob::eightBit (then empty)
    ByteImage bytes;  // with RenderJob::eightBit (else empty)
    RenderStats stats;
    bool interrupted = false;  // stopped by RenderJob::cancel: the image is partial
};

// Whether text is a device selection: auto, cpu, gpu, all, ref (or reference), or a
// device index, or a list of indices such as 0,2.
bool isDeviceSelection(const std::string& text);

// "ref" or "reference": the host reference renderer rather than OpenCL devices.
bool isReferenceDevice(const std::string& device);

// The most samples a pixel takes with the settings' antialiasing (for the statistics).
int maxSamplesPerPixel(const RenderSettings& settings);

// Renders on the devices the job names; several ("all", a list) cooperate on the frame,
// tile by tile (opencl/opencl_engine.h). Throws DeviceError, InputError.
RenderOutput render(const RenderJob& job);

// The side of the square tiles of a cancellable render (RenderJob::cancel set), a multiple
// of the 8x8 work-group from 8 to 64: small enough that the few tiles already queued when
// it is cancelled finish within about a second on PoCL, given the samples per pixel and
// the shadow rays of the scene's area lights.
int cancellableTileSize(const RenderSettings& settings, const Scene& scene);

// Starts what a render on `device` will need on a thread of its own (the OpenCL drivers;
// nothing for the reference), so that it overlaps the scene's load. The thread is joined
// when the returned object is destroyed.
std::jthread startDeviceEarly(const std::string& device);

// Prints every OpenCL platform and device with its index (--list-devices).
void printDeviceList(std::ostream& out);

}  // namespace ray
