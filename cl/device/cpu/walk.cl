/* The scene's walk on a CPU (walkScene, for traceBvh: cl/traversal/trace.cl): the
 * sixteen-wide tree (RayCpuBvhNode, cl/shared_types.h). The children of a node are tested in
 * one float16 slab test, and the children entered become bit masks, so that a step's
 * branches are one per leaf entered and one on how many inner children are, rather than two
 * a child. Below the sixteen-wide nodes the walk goes on in the four-wide tree (fourWideStep,
 * children of count -1), one stack holding nodes of both. The stack holds the up to fifteen
 * children a step pushes: three times RAY_BVH_SHORT_STACK (a test's tiny short stack still
 * makes it overflow). */
#ifdef RAY_DEVICE_CPU

#define RAY_CPU_BVH_STACK (3 * RAY_BVH_SHORT_STACK)

static inline bool isFourWideRef(int next) { return next <= -3; } /* fourWideRef */

RAY_DEFINE_SLAB_ENTRY(boxEntries16, float16, int16)

/* The distance at which the ray enters each of the sixteen children's boxes within
 * (0, tMax), +infinity for a child it misses and for an absent one. */
static inline float16 cpuChildEntryDistances(__global const RayCpuBvhNode* node, float3 origin,
                                             float3 inverseDirection, float tMax) {
    return boxEntries16(node->minX, node->maxX, node->minY, node->maxY, node->minZ, node->maxZ, (float16)(origin.x),
                        (float16)(origin.y), (float16)(origin.z), (float16)(inverseDirection.x),
                        (float16)(inverseDirection.y), (float16)(inverseDirection.z), (float16)(tMax),
                        node->index >= 0);
}

/* The lanes of a comparison's result (-1: true) as bits, lane c as bit c. */
static inline uint laneBits(int16 lanes) {
    int16 bits = lanes & (int16)(1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768);
    int8 b8 = bits.lo | bits.hi;
    int4 b4 = b8.lo | b8.hi;
    int2 b2 = b4.lo | b4.hi;
    return (uint)(b2.x | b2.y);
}

/* The lowest bit set (of a non-zero mask), and the mask without it. */
static inline int takeLowestLane(uint* bits) {
    uint lowest = *bits & (0u - *bits);
    *bits ^= lowest;
    return 31 - (int)clz(lowest);
}

/* Inner child c of a sixteen-wide node as the walk holds it: a node of the sixteen-wide
 * tree, or (count -1) a reference into the four-wide one (fourWideRef). */
static inline int cpuInnerChild(__global const RayCpuBvhNode* node, int c) {
    const int index = ((__global const int*)&node->index)[c];
    return ((__global const int*)&node->count)[c] == 0 ? index : fourWideRef(index);
}

/* nextNode for a sixteen-wide node whose inner children `inners` (bits) the ray enters by
 * `limit`: descend into the nearest (closest hits; anyHit: the last in node order) and push
 * the others, the farthest deepest, or resume from the stack. */
static inline int nextCpuNode(__global const RayCpuBvhNode* node, float16 entry, uint inners, bool anyHit,
                              BvhStack* stack, float limit) {
    if (inners != 0 && (inners & (inners - 1)) == 0) return cpuInnerChild(node, takeLowestLane(&inners)); /* one */
    if (inners == 0) return popNode(stack, limit);
    float entries[RAY_CPU_BVH_WIDTH];
    vstore16(entry, 0, entries);
    int child[RAY_CPU_BVH_WIDTH];
    float key[RAY_CPU_BVH_WIDTH];
    int n = 0;
    while (inners != 0) { /* farthest first */
        int c = takeLowestLane(&inners), i = n++;
        while (!anyHit && i > 0 && key[i - 1] < entries[c]) {
            child[i] = child[i - 1];
            key[i] = key[i - 1];
            --i;
        }
        child[i] = cpuInnerChild(node, c);
        key[i] = entries[c];
    }
    for (int i = 0; i + 1 < n; ++i)
        if (!pushNode(stack, child[i], key[i])) return -1;
    return child[n - 1];
}

static inline RAY_INLINED_ON_GPU
void walkScene(__global const RayWideBvhNode* nodes, __global const RayCpuBvhNode* cpuNodes,
               __global const RayPrimitive* prims, __global const RayTriangle4* triangles,
               __global const float4* motions, Ray ray, float3 inverseDirection, bool anyHit, bool courseMeshes,
               Hit* hit) {
    BvhStackEntry entries[RAY_CPU_BVH_STACK];
    BvhStack stack = emptyBvhStack(entries, RAY_CPU_BVH_STACK);
    int next = 0;
    do {
        if (next == RAY_WALK_EVERY_PRIMITIVE || isFourWideRef(next)) { /* in the four-wide tree */
            next = fourWideStep(nodes, prims, triangles, motions, ray, inverseDirection, anyHit, courseMeshes, true,
                                &stack, next == RAY_WALK_EVERY_PRIMITIVE ? next : fourWideRef(next), hit);
            continue;
        }
        float limit = pruneDistance(hit, courseMeshes); /* read as fourWideStep reads it */
        __global const RayCpuBvhNode* node = &cpuNodes[next];
        float16 entry = cpuChildEntryDistances(node, ray.origin, inverseDirection, limit);
        int16 count = node->count;
        int16 entered = (entry <= (float16)(limit)) & (entry < (float16)(RAY_INFINITY)); /* enteredBy, a lane a child */
        uint leaves = laneBits(entered & (count > (int16)(0)));
        uint inners = laneBits(entered & (count <= (int16)(0)));
        if (leaves != 0) {
            while (leaves != 0) {
                int c = takeLowestLane(&leaves);
                intersectLeaf(nodes, prims, triangles, motions, ray, courseMeshes, &stack,
                              ((__global const int*)&node->index)[c], ((__global const int*)&node->count)[c], hit);
                if (anyHitFound(anyHit, hit)) break;
                limit = pruneDistance(hit, courseMeshes);
            }
            if (anyHitFound(anyHit, hit)) break;
            inners &= laneBits(entry <= (float16)(limit)); /* the leaves' hits may have narrowed it */
        }
        next = afterOverflow(nextCpuNode(node, entry, inners, anyHit, &stack, limit), &stack);
    } while (next != -1);
}

#endif
