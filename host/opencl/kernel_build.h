// The kernel a device of the engine runs: the build options that choose its path (its
// variant, kernel_variant.h; the frame count of the depth's bucket; the test hooks' stack), and its program built
// (or taken from the disk cache, opencl_device.h buildKernelProgram) and run once.
#pragma once

#include <string>

#include "core/test_hooks.h"
#include "opencl/device_slot.h"
#include "opencl/opencl_device.h"
#include "opencl/scene_packing.h"

namespace ray::engine {

// How many ray-tree frames the kernel is built with for a maximum depth (-DRAY_MAX_FRAMES,
// cl/render/ray_tree.cl): the depth itself is a launch parameter, and the frame count the smallest of
// a few buckets that holds it (depths up to 4, 10, 16 and kMaxDepth), so that a user who
// tries depth after depth waits for a build once a bucket. The first bucket is the GPU's
// budget (docs/performance.md, "The kernel on GPUs"): the default depth, 4, keeps the
// private memory it had when each depth was its own build. The buckets stay small because a
// CPU work-item holds a ray tree for each of its packet's lanes.
int kernelFrames(int maxDepth);

// The options the kernel is built with for a frame count (kernelFrames) and the device's variant.
std::string buildOptions(int frames, const KernelVariant& variant, const TestHooks& hooks);

// The slot's program for a frame count (kernelFrames), built in its context and run once on a tile of no
// pixels with the scene's buffers bound (they must be uploaded), so that PoCL compiles the
// launch's work-group function here rather than in the frame's first tile. Throws
// DeviceError (the build log) and cl::Error.
DeviceSlot::Program buildDeviceProgram(DeviceSlot& slot, int frames, const gpu::RayRenderParams& frameParams);

}  // namespace ray::engine
