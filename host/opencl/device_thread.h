// A device's thread in the OpenCL engine, kept for the engine's life: it serves the newest
// frame the engine posts to its slot, one after another. For each it prepares the device
// (scene checked against its limits and uploaded where it changed, the kernel built for the
// frame's depth, tile outputs sized), then renders tiles (device_worker.h) if the frame still
// wants it. Each device starts as soon as its own scene is uploaded and kernel built: a slow
// first build (a GPU driver's can take minutes) holds back no other device, and a device
// still building when the frame is done takes no part in it and keeps building, for the next.
// A device that fails is dropped, its tiles going to the others.
#pragma once

#include <memory>

#include "opencl/device_slot.h"

namespace ray::engine {

// The thread's body: returns when the engine stops it or the device is dropped.
void serveFrames(std::shared_ptr<DeviceSlot> slot);

}  // namespace ray::engine
