// One device's tiles of a frame, once its scene is uploaded and its kernel built
// (device_thread.h): it takes tiles from the frame's scheduler, keeps kTilesInFlight
// launches in its in-order queue, each launch's reads queued right behind its kernel, and
// keeps each tile that comes back unless another device was first. When no tile is left
// to hand out, an idle device renders a copy of one still pending on another.
#pragma once

#include "opencl/device_slot.h"
#include "opencl/engine_frame.h"

namespace ray::engine {

// Renders tiles of the frame on the slot's device until the frame has none left for it, is
// cancelled or closed, or no longer counts the device in. Throws DeviceError or cl::Error
// when the device fails (the caller drops it).
void renderTiles(Frame& frame, DeviceSlot& slot, cl::Kernel& kernel);

}  // namespace ray::engine
