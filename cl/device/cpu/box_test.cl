/* How a CPU tests a four-wide node's children (childEntryDistances, whose callers are in
 * cl/traversal/wide_walk.cl): the four at once, lane c child c, in float4s, which PoCL's CPU
 * code runs as SIMD. A GPU tests them a box at a time (cl/device/gpu/box_test.cl). */
#ifdef RAY_DEVICE_CPU

RAY_DEFINE_SLAB_ENTRY(boxEntries4, float4, int4)

/* The distance at which the ray enters each child's box within (0, tMax), +infinity for a
 * child it misses and for an absent one. */
static inline float4 childEntryDistances(__global const RayWideBvhNode* node, float3 origin, float3 inverseDirection,
                                         float tMax) {
    return boxEntries4(node->minX, node->maxX, node->minY, node->maxY, node->minZ, node->maxZ, (float4)(origin.x),
                       (float4)(origin.y), (float4)(origin.z), (float4)(inverseDirection.x),
                       (float4)(inverseDirection.y), (float4)(inverseDirection.z), (float4)(tMax), node->index >= 0);
}

#endif
