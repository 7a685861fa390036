// renderTile's arguments (cl/kernel.cl), numbered as the kernel declares them: the launch
// parameters, the scene's buffers in the order of their list (cl/shared_types.h
// RAY_SCENE_BUFFERS), then the tile's outputs, and on the packet path (CPU devices) its block
// queue (cl/kernel.cl). Computed from the list, never numbered by hand.
#pragma once

#include <cstdint>

#include "opencl/scene_packing.h"

namespace ray::kernel_argument {

constexpr uint32_t kParams = 0;                                   // RayRenderParams, by value
constexpr uint32_t kFirstSceneBuffer = kParams + 1;               // then kSceneBufferCount of them
constexpr uint32_t kTileColors = kFirstSceneBuffer + uint32_t(kSceneBufferCount);  // float4 a pixel
constexpr uint32_t kTileRayCounts = kTileColors + 1;              // uint4 a pixel (a block: packets)
constexpr uint32_t kBlockQueue = kTileRayCounts + 1;              // packet builds alone: 2 uint

// How many the kernel declares: a packet build (KernelVariant::lanes > 1) has the block queue too.
constexpr uint32_t count(bool packetBuild) { return packetBuild ? kBlockQueue + 1 : kBlockQueue; }

}  // namespace ray::kernel_argument
