// A packed scene onto a device of the engine: whether it fits the device (and the host's
// memory) at all, and its tables uploaded as the device's buffers.
#pragma once

#include <cstddef>
#include <memory>

#include "opencl/device_slot.h"
#include "opencl/kernel_variant.h"
#include "opencl/opencl_device.h"
#include "opencl/scene_packing.h"

namespace ray::engine {

// Refuses, before any upload, a scene whose buffers (those the variant's kernel reads) exceed
// what the device allows, with kTilesInFlight tiles of tileBytes each in flight. Throws
// DeviceError with advice.
void checkDeviceLimits(const OpenClDevice& device, const KernelVariant& variant, const PackedScene& packed,
                       size_t tileBytes);

// Uploads the tables of `packed` that the slot does not hold at their version (every one for
// a new packing, only those an edit changed for a repacked one). A CPU device reads the
// host's tables in place, so that each buffer keeps the packing it came from alive: its
// buffers of the tables an edit kept are made again over `packed`'s (no copy), so that it
// holds one packing, not the old one beside the new. Other devices get a copy in their
// memory and hold no packing. A table the slot's kernel does not read
// (KernelVariant::reads) becomes a buffer of one unused element. Returns whether any table
// was uploaded (copied or changed).
bool uploadScene(DeviceSlot& slot, const std::shared_ptr<const PackedScene>& packed);

}  // namespace ray::engine
