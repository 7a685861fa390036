/* How a GPU tests a four-wide node's children (childEntryDistances, whose callers are in
 * cl/traversal/wide_walk.cl): one child at a time, in floats. On a GPU each work-item's
 * float4 is four scalar registers, and a ray's coordinates spread over float4s (origin.x -
 * node->minX and the like) become six four-register splats that LLVM hoists out of the walk's
 * loop and holds for the whole walk (docs/performance.md, "The kernel on GPUs"). A CPU tests
 * the four at once (cl/device/cpu/box_test.cl); tests/rusticl.sh renders the bundled scenes
 * with this form on llvmpipe and compares them with PoCL's. */
#ifndef RAY_DEVICE_CPU

RAY_DEFINE_SLAB_ENTRY(boxEntry, float, int)

/* Child `lane` (s0..s3) of the node: its box's entry distance, +infinity when absent. */
#define RAY_CHILD_ENTRY(lane)                                                                                      \
    (node->index.lane >= 0 ? boxEntry(node->minX.lane, node->maxX.lane, node->minY.lane, node->maxY.lane,           \
                                      node->minZ.lane, node->maxZ.lane, origin.x, origin.y, origin.z,               \
                                      inverseDirection.x, inverseDirection.y, inverseDirection.z, tMax, 1)          \
                           : RAY_INFINITY)
/* The distance at which the ray enters each child's box within (0, tMax), +infinity for a
 * child it misses and for an absent one. */
static inline float4 childEntryDistances(__global const RayWideBvhNode* node, float3 origin, float3 inverseDirection,
                                         float tMax) {
    return (float4)(RAY_CHILD_ENTRY(s0), RAY_CHILD_ENTRY(s1), RAY_CHILD_ENTRY(s2), RAY_CHILD_ENTRY(s3));
}
#undef RAY_CHILD_ENTRY

#endif
