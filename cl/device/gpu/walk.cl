/* The scene's walk on a GPU (walkScene, for traceBvh: cl/traversal/trace.cl): the
 * four-wide tree, a step at a time (fourWideStep), the children of a node tested a box at a
 * time (cl/device/gpu/box_test.cl). */
#ifndef RAY_DEVICE_CPU

static inline RAY_INLINED_ON_GPU
void walkScene(__global const RayWideBvhNode* nodes, __global const RayCpuBvhNode* cpuNodes,
               __global const RayPrimitive* prims, __global const RayTriangle4* triangles,
               __global const float4* motions, Ray ray, float3 inverseDirection, bool anyHit, bool courseMeshes,
               Hit* hit) {
    (void)cpuNodes; /* a CPU's tree (cl/device/cpu/walk.cl): a placeholder here */
    BvhStackEntry entries[RAY_BVH_SHORT_STACK];
    BvhStack stack = emptyBvhStack(entries, RAY_BVH_SHORT_STACK);
    int next = 0;
    do {
        next = fourWideStep(nodes, prims, triangles, motions, ray, inverseDirection, anyHit, courseMeshes, false,
                            &stack, next, hit);
    } while (next != -1);
}

#endif
