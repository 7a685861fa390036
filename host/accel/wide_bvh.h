// Collapsing the binary BVH into the four-wide one the kernel walks (the node layout and
// why: RayWideBvhNode in cl/shared_types.h).
#pragma once

#include <vector>

#include "accel/bvh.h"
#include "shared_types.h"

namespace ray {

// Each wide node takes a binary node's children and keeps opening the inner child of
// largest surface area (the one a ray most likely enters) until it has four children or
// only leaves. Leaves keep their primitive ranges, so the primitive order is unchanged.
// Child indices of inner nodes refer to the returned array (its node 0 is the root);
// `binary` must be a tree from buildBvh (node 0 its root).
std::vector<gpu::RayWideBvhNode> widenBvh(const std::vector<BinaryBvhNode>& binary);

// The sixteen-wide tree that CPU devices walk a ray at a time (RayCpuBvhNode in
// cl/shared_types.h), collapsed from the four-wide tree under wide[0] (the scene's; the
// meshes' nodes that follow it are not reached): a node takes a four-wide node's children
// and keeps opening the inner child of largest surface area whose children still fit in
// sixteen. Leaves keep their primitive ranges; an inner child whose own node would have
// fewer than eight children stays a node of `wide` (count -1).
std::vector<gpu::RayCpuBvhNode> widenBvhForCpu(const std::vector<gpu::RayWideBvhNode>& wide);

}  // namespace ray
