/* The packet walk: RAY_PACKET_WIDTH rays through the scene's BVH at once, for CPU devices
 * (cl/packet_render.cl). Built only when the host passes -DRAY_PACKET_WIDTH (4, 8 or 16:
 * the device's CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT); GPUs never see it.
 *
 * Why: PoCL runs traceBvh, one ray per work-item, as scalar code (its control flow is too
 * divergent to vectorise across work-items), so a CPU's 8- or 16-wide vector units idle.
 * Here a node's box is tested for every ray of the packet in one floatN slab test, and the
 * walk descends into a child while any ray of the packet enters it. Leaves are intersected
 * ray by ray with the single-ray walk's own intersectPrimitive, for the rays that enter the
 * leaf's box within their nearest hit so far: every ray gets exactly the hit traceBvh gives
 * it (hits are ranked by distance and then by order, Hit.order, whatever the order in
 * which they are found), so the images are the single-ray path's to the bit.
 *
 * The lanes' entry distances travel on the stack with their node, so that a node popped
 * after every ray found something nearer is skipped, as the single-ray walk skips it. */

#ifdef RAY_PACKET_WIDTH

#if RAY_PACKET_WIDTH == 16
typedef float16 PacketFloat;
typedef int16 PacketInt;
#define RAY_PACKET_LOAD(pointer) vload16(0, pointer)
#define RAY_PACKET_STORE(value, pointer) vstore16(value, 0, pointer)
#elif RAY_PACKET_WIDTH == 8
typedef float8 PacketFloat;
typedef int8 PacketInt;
#define RAY_PACKET_LOAD(pointer) vload8(0, pointer)
#define RAY_PACKET_STORE(value, pointer) vstore8(value, 0, pointer)
#elif RAY_PACKET_WIDTH == 4
typedef float4 PacketFloat;
typedef int4 PacketInt;
#define RAY_PACKET_LOAD(pointer) vload4(0, pointer)
#define RAY_PACKET_STORE(value, pointer) vstore4(value, 0, pointer)
#else
#error "RAY_PACKET_WIDTH must be 4, 8 or 16"
#endif

/* The smallest lane of a packet: halves folded onto each other. */
static inline float packetMinimum(PacketFloat v) {
#if RAY_PACKET_WIDTH == 16
    float8 v8 = fmin(v.lo, v.hi);
#elif RAY_PACKET_WIDTH == 8
    float8 v8 = v;
#endif
#if RAY_PACKET_WIDTH >= 8
    float4 v4 = fmin(v8.lo, v8.hi);
#else
    float4 v4 = v;
#endif
    float2 v2 = fmin(v4.lo, v4.hi);
    return fmin(v2.x, v2.y);
}

/* The rays of a packet as the box tests read them: origins and safe inverse directions
 * (safeInverse), one vector a coordinate. */
typedef struct {
    PacketFloat originX, originY, originZ;
    PacketFloat inverseX, inverseY, inverseZ;
} PacketRays;

static inline PacketRays packetRays(const Ray* rays) {
    float ox[RAY_PACKET_WIDTH], oy[RAY_PACKET_WIDTH], oz[RAY_PACKET_WIDTH];
    float ix[RAY_PACKET_WIDTH], iy[RAY_PACKET_WIDTH], iz[RAY_PACKET_WIDTH];
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        float3 inverse = safeInverse(rays[l].direction);
        ox[l] = rays[l].origin.x;
        oy[l] = rays[l].origin.y;
        oz[l] = rays[l].origin.z;
        ix[l] = inverse.x;
        iy[l] = inverse.y;
        iz[l] = inverse.z;
    }
    PacketRays p = {RAY_PACKET_LOAD(ox), RAY_PACKET_LOAD(oy), RAY_PACKET_LOAD(oz),
                    RAY_PACKET_LOAD(ix), RAY_PACKET_LOAD(iy), RAY_PACKET_LOAD(iz)};
    return p;
}

/* Minimum and maximum of operands that are never NaN, as one select each (see minNumber4). */
static inline PacketFloat packetMin(PacketFloat a, PacketFloat b) { return select(b, a, a < b); }
static inline PacketFloat packetMax(PacketFloat a, PacketFloat b) { return select(b, a, a > b); }

/* Every ray's entry distance into child `c` of a wide node within (0, limit), +infinity
 * for a ray that misses it: boxEntryDistance's arithmetic, a lane a ray. A lane whose
 * limit is negative (a finished ray) always misses. */
static inline PacketFloat packetChildEntry(__global const RayWideBvhNode* node, int c, const PacketRays* r,
                                           PacketFloat limit) {
    float minX = ((__global const float*)&node->minX)[c], maxX = ((__global const float*)&node->maxX)[c];
    float minY = ((__global const float*)&node->minY)[c], maxY = ((__global const float*)&node->maxY)[c];
    float minZ = ((__global const float*)&node->minZ)[c], maxZ = ((__global const float*)&node->maxZ)[c];
    PacketFloat tx0 = (minX - r->originX) * r->inverseX, tx1 = (maxX - r->originX) * r->inverseX;
    PacketFloat ty0 = (minY - r->originY) * r->inverseY, ty1 = (maxY - r->originY) * r->inverseY;
    PacketFloat tz0 = (minZ - r->originZ) * r->inverseZ, tz1 = (maxZ - r->originZ) * r->inverseZ;
    PacketFloat tNear = packetMax(packetMax(packetMin(tx0, tx1), packetMin(ty0, ty1)),
                                  packetMax(packetMin(tz0, tz1), (PacketFloat)(0.0f)));
    PacketFloat tFar = packetMin(packetMin(packetMax(tx0, tx1), packetMax(ty0, ty1)),
                                 packetMin(packetMax(tz0, tz1), limit));
    return select((PacketFloat)(RAY_INFINITY), tNear, tNear <= tFar);
}

/* The lanes a child is to be visited for (enteredBy, a lane a ray). */
static inline PacketInt packetEntered(PacketFloat entry, PacketFloat limit) {
    return (entry <= limit) & (entry < (PacketFloat)(RAY_INFINITY));
}

/* One node still to visit and each ray's distance into it (+infinity: not entered). */
typedef struct {
    PacketFloat entry;
    int node;
} PacketStackEntry;

/* The packet walk's stack: deep enough for every walk of the bundled and course scenes
 * (as RAY_BVH_SHORT_STACK is for one ray's); a walk that would push more is finished by
 * each of its rays' own single-ray walk (traceBvh), which finds the same hits. */
#ifndef RAY_PACKET_STACK
#define RAY_PACKET_STACK 32
#endif

/* The state of the rays of one walk, a lane a ray: limit is the prune distance of each
 * (pruneDistance), negative once it is done (an any-hit ray that found its blocker, or a
 * lane the walk was not asked to trace). */
typedef union {
    PacketFloat vector;
    float lane[RAY_PACKET_WIDTH];
} PacketLanes;

/* Intersects the primitives [first, first + count) for the rays of `entering`, then brings
 * their limits up to date; with anyHit a ray that hit something is done. */
static inline void packetLeaf(__global const RayWideBvhNode* nodes, __global const RayPrimitive* prims,
                              __global const RayTriangle* triangles, __global const float4* motions,
                              const Ray* rays, PacketInt entering, int first, int count, bool anyHit,
                              bool courseMeshes, BvhStackEntry* spare, Hit* hits, PacketLanes* limits) {
    int lanes[RAY_PACKET_WIDTH];
    RAY_PACKET_STORE(entering, lanes);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        if (!lanes[l]) continue;
        for (int i = first; i < first + count; ++i)
            intersectPrimitive(nodes, triangles, motions, &prims[i], i, rays[l], courseMeshes, spare,
                               RAY_BVH_SHORT_STACK, &hits[l]);
        limits->lane[l] = anyHitFound(anyHit, &hits[l]) ? -1.0f : pruneDistance(&hits[l], courseMeshes);
    }
}

/* traceBvh for the rays of `lanes` (non-zero: trace it) at once, each below its own tMax:
 * hits[l] as traceBvh(rays[l], tMax[l], ...) gives it; lanes not traced keep hits[l] as
 * they were. The children of a node are visited nearest first for the packet's nearest ray
 * (closest hits), or in node order (anyHit). */
RAY_CALL_ON_POCL void traceBvhPacket(__global const RayWideBvhNode* nodes, __global const RayPrimitive* prims,
                                     __global const RayTriangle* triangles, __global const float4* motions,
                                     const Ray* rays, const float* tMax, const int* lanes, bool anyHit,
                                     bool courseMeshes, Hit* hits) {
    PacketLanes limits;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        limits.lane[l] = -1.0f;
        if (!lanes[l]) continue;
        hits[l].t = tMax[l];
        hits[l].primitive = -1;
        hits[l].order = 0;
        limits.lane[l] = courseMeshes ? RAY_INFINITY : tMax[l];
    }
    const PacketRays packet = packetRays(rays);
    BvhStackEntry spare[RAY_BVH_SHORT_STACK]; /* the mesh walks' (intersectMesh) */
    PacketStackEntry stack[RAY_PACKET_STACK];
    int top = 0;
    int next = 0;
    bool overflowed = false;
    while (next >= 0) {
        __global const RayWideBvhNode* node = &nodes[next];
        /* the inner children entered, nearest (for the packet's nearest ray) last */
        PacketStackEntry inner[4];
        float key[4];
        int innerCount = 0;
        for (int c = 0; c < 4; ++c) {
            const int index = ((__global const int*)&node->index)[c];
            if (index < 0) continue;
            PacketFloat entry = packetChildEntry(node, c, &packet, limits.vector);
            PacketInt entering = packetEntered(entry, limits.vector);
            if (!any(entering)) continue;
            const int count = ((__global const int*)&node->count)[c];
            if (count > 0) {
                packetLeaf(nodes, prims, triangles, motions, rays, entering, index, count, anyHit, courseMeshes,
                           spare, hits, &limits);
                continue;
            }
            int i = innerCount++;
            float nearest = anyHit ? 0.0f : packetMinimum(entry);
            while (i > 0 && key[i - 1] < nearest) {
                inner[i] = inner[i - 1];
                key[i] = key[i - 1];
                --i;
            }
            inner[i].entry = entry;
            inner[i].node = index;
            key[i] = nearest;
        }
        /* As nextNode: descend into the nearest child still entered, push the others (the
         * farthest deepest), or resume from the stack. */
        int chosen = -1;
        for (int i = 0; i < innerCount && !overflowed; ++i) {
            if (!any(packetEntered(inner[i].entry, limits.vector))) continue;
            if (chosen >= 0) {
                if (top == RAY_PACKET_STACK) overflowed = true;
                else stack[top++] = inner[chosen];
            }
            chosen = i;
        }
        if (overflowed) break;
        next = chosen >= 0 ? inner[chosen].node : -1;
        while (next < 0 && top > 0) {
            --top;
            if (any(packetEntered(stack[top].entry, limits.vector))) next = stack[top].node;
        }
    }
    if (!overflowed) return;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l)
        if (lanes[l]) traceBvh(nodes, prims, triangles, motions, rays[l], tMax[l], anyHit, courseMeshes, &hits[l]);
}

#endif /* RAY_PACKET_WIDTH */
