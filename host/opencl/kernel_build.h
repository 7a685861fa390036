// The kernel a device of the engine runs: the build options that choose its path (its
// variant, kernel_variant.h; the depth; the test hooks' stack), and its program built
// (or taken from the disk cache, opencl_device.h buildKernelProgram) and run once.
#pragma once

#include <string>

#include "core/test_hooks.h"
#include "opencl/device_slot.h"
#include "opencl/opencl_device.h"
#include "opencl/scene_packing.h"

namespace ray::engine {

// The options the kernel is built with for a maximum depth and the device's variant.
std::string buildOptions(int maxDepth, const KernelVariant& variant, const TestHooks& hooks);

// The slot's program for a maximum depth, built in its context and run once on a tile of no
// pixels with the scene's buffers bound (they must be uploaded), so that PoCL compiles the
// launch's work-group function here rather than in the frame's first tile. Throws
// DeviceError (the build log) and cl::Error.
DeviceSlot::Program buildDeviceProgram(DeviceSlot& slot, int maxDepth, const gpu::RayRenderParams& frameParams);

}  // namespace ray::engine
