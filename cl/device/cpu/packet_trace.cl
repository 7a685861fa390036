/* The packet walk: RAY_PACKET_WIDTH rays through the scene's BVH at once, for CPU devices
 * (cl/device/cpu/packet_render.cl), in a packet build (cl/device/variant.h).
 *
 * Why: PoCL runs traceBvh, one ray per work-item, as scalar code (its control flow is too
 * divergent to vectorise across work-items), so a CPU's 8- or 16-wide vector units idle.
 * Here a node's box is tested for every ray of the packet in one slab test (a lane a ray),
 * and the walk descends into a child while any ray of the packet enters it. A leaf's
 * primitives are intersected for the rays that enter its box within their nearest hit so
 * far: the convex shapes for those rays at once (packetIntersectPrimitive, with the packet
 * instance of cl/geometry/shapes.cl), a mesh by walking its own tree with the packet and
 * testing each triangle for every ray at once (packetIntersectMesh, with the packet instance
 * of cl/geometry/triangle.cl), the others ray by ray with one ray's intersectPrimitive.
 * Every ray gets exactly the hit traceBvh gives it (hits are ranked by distance and then by
 * order, hitLimit, and a mesh's triangles by distance and then by index, whatever the order
 * in which they are found), so the images are the single-ray path's to the bit.
 *
 * The lanes' entry distances travel on the stack with their node (BvhStackPacket,
 * cl/traversal/stack.cl), so that a node popped after every ray found something nearer is
 * skipped, as the single-ray walk skips it. */

#ifdef RAY_PACKET_WIDTH

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

/* The rays of a packet as the box tests and the shape tests read them: origins, safe
 * inverse directions (safeInverse) and directions. */
typedef struct {
    PacketVec3 origin, inverse, direction;
} PacketRays;

/* safeInverse for every lane at once: the division is IEEE's in a vector as in one lane,
 * so the bits are one ray's, without a packet's 3 × RAY_PACKET_WIDTH scalar divisions at
 * the start of every walk (a shadow packet's walk is short). */
static inline PacketFloat packetSafeInverse(PacketFloat d) {
    const PacketFloat tiny = (PacketFloat)(1e-20f);
    return (PacketFloat)(1.0f) / select(copysign(tiny, d), d, fabs(d) > tiny);
}

static inline PacketRays packetRays(const Ray* rays) {
    float ox[RAY_PACKET_WIDTH], oy[RAY_PACKET_WIDTH], oz[RAY_PACKET_WIDTH];
    float dx[RAY_PACKET_WIDTH], dy[RAY_PACKET_WIDTH], dz[RAY_PACKET_WIDTH];
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        ox[l] = rays[l].origin.x;
        oy[l] = rays[l].origin.y;
        oz[l] = rays[l].origin.z;
        dx[l] = rays[l].direction.x;
        dy[l] = rays[l].direction.y;
        dz[l] = rays[l].direction.z;
    }
    PacketVec3 direction = packetVec3(RAY_PACKET_LOAD(dx), RAY_PACKET_LOAD(dy), RAY_PACKET_LOAD(dz));
    PacketRays p = {packetVec3(RAY_PACKET_LOAD(ox), RAY_PACKET_LOAD(oy), RAY_PACKET_LOAD(oz)),
                    packetVec3(packetSafeInverse(direction.x), packetSafeInverse(direction.y),
                               packetSafeInverse(direction.z)),
                    direction};
    return p;
}

RAY_DEFINE_SLAB_ENTRY(boxEntryPacket, PacketFloat, PacketInt)

/* Every ray's entry distance into child `c` of a wide node within (0, limit), +infinity
 * for a ray that misses it. A lane whose limit is negative (a finished ray) always misses. */
static inline PacketFloat packetChildEntry(__global const RayWideBvhNode* node, int c, const PacketRays* r,
                                           PacketFloat limit) {
#define RAY_BOUND(bound) ((PacketFloat)(((__global const float*)&node->bound)[c]))
    return boxEntryPacket(RAY_BOUND(minX), RAY_BOUND(maxX), RAY_BOUND(minY), RAY_BOUND(maxY), RAY_BOUND(minZ),
                          RAY_BOUND(maxZ), r->origin.x, r->origin.y, r->origin.z, r->inverse.x, r->inverse.y,
                          r->inverse.z, limit, (PacketInt)(-1));
#undef RAY_BOUND
}

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

typedef union {
    PacketInt vector;
    int lane[RAY_PACKET_WIDTH];
} PacketIntLanes;

/* What the walk compares hits by, a lane a ray: hits[l].t, .primitive and .order, kept in
 * step with hits[] (which holds the rest of each hit). */
typedef struct {
    PacketLanes t;
    PacketIntLanes primitive, order;
} PacketHitKeys;

static inline void keepHitKeys(PacketHitKeys* keys, int l, const Hit* hit) {
    keys->t.lane[l] = hit->t;
    keys->primitive.lane[l] = hit->primitive;
    keys->order.lane[l] = hit->order;
}

/* A lane's new nearest hit, as one ray's walk records it. */
static inline void takeHit(Hit* hit, float t, int index, int order, int part, float3 objectPoint, float3 objectNormal,
                           float2 barycentric) {
    hit->t = t;
    hit->primitive = index;
    hit->order = order;
    hit->part = part;
    hit->objectPoint = objectPoint;
    hit->objectNormal = objectNormal;
    hit->barycentric = barycentric;
}

/* The lanes of `better` now rank their hits by primitive `index` at distance `best`. */
static inline void keepPacketKeys(PacketHitKeys* keys, PacketFloat best, int index, int order, PacketInt better) {
    keys->t.vector = select(keys->t.vector, best, better);
    keys->primitive.vector = select(keys->primitive.vector, (PacketInt)(index), better);
    keys->order.vector = select(keys->order.vector, (PacketInt)(order), better);
}

/* intersectPrimitive for the rays of `entering` and one primitive of a convex shape
 * (convexShape), the rays carried into its object space in vectors; hits[l] changes as
 * intersectPrimitive changes it (no motion: the caller leaves moving rays to it). */
static inline void packetIntersectPrimitive(__global const RayPrimitive* prim, int index, const PacketRays* r,
                                            PacketInt entering, PacketHitKeys* keys, Hit* hits) {
    PacketVec3 o = transformPointPacket(prim->worldToObject, r->origin);
    PacketVec3 d = transformVectorPacket(prim->worldToObject, r->direction);
    const int order = prim->order;
    PacketFloat limit = hitLimitPacket(keys->t.vector, keys->primitive.vector, keys->order.vector, order);
    ShapeHitPacket h = {select((PacketFloat)(-1.0f), limit, entering), (PacketInt)(0),
                        packetVec3((PacketFloat)(0.0f), (PacketFloat)(0.0f), (PacketFloat)(0.0f))};
    intersectConvexShapePacket(prim->type, o, d, &h);
    PacketInt better = entering & (h.best < limit);
    if (!packetAny(better)) return;
    int take[RAY_PACKET_WIDTH], part[RAY_PACKET_WIDTH];
    float t[RAY_PACKET_WIDTH], px[RAY_PACKET_WIDTH], py[RAY_PACKET_WIDTH], pz[RAY_PACKET_WIDTH];
    float nx[RAY_PACKET_WIDTH], ny[RAY_PACKET_WIDTH], nz[RAY_PACKET_WIDTH];
    RAY_PACKET_STORE(better, take);
    RAY_PACKET_STORE(h.part, part);
    RAY_PACKET_STORE(h.best, t);
    RAY_PACKET_STORE(o.x + h.best * d.x, px); /* o + best * d */
    RAY_PACKET_STORE(o.y + h.best * d.y, py);
    RAY_PACKET_STORE(o.z + h.best * d.z, pz);
    RAY_PACKET_STORE(h.normal.x, nx);
    RAY_PACKET_STORE(h.normal.y, ny);
    RAY_PACKET_STORE(h.normal.z, nz);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        if (!take[l]) continue;
        takeHit(&hits[l], t[l], index, order, part[l], (float3)(px[l], py[l], pz[l]), (float3)(nx[l], ny[l], nz[l]),
                (float2)(0.0f));
    }
    keepPacketKeys(keys, h.best, index, order, better);
}

/* safeInverse, a lane a ray. */
static inline PacketVec3 safeInversePacket(PacketVec3 d) {
    const PacketFloat tiny = (PacketFloat)(1e-20f);
    return packetVec3(1.0f / select(copysign(tiny, d.x), d.x, fabs(d.x) > tiny),
                      1.0f / select(copysign(tiny, d.y), d.y, fabs(d.y) > tiny),
                      1.0f / select(copysign(tiny, d.z), d.z, fabs(d.z) > tiny));
}

/* Adds inner child `node`, entered at `entry`, to a node's inner children, kept farthest
 * first by `nearest` (the packet's nearest entry; a constant keeps node order). */
static inline void addInnerPacket(BvhStackEntryPacket* inner, float* key, int* count, int node, PacketFloat entry,
                                  float nearest) {
    int i = (*count)++;
    while (i > 0 && key[i - 1] < nearest) {
        inner[i] = inner[i - 1];
        key[i] = key[i - 1];
        --i;
    }
    inner[i].entry = entry;
    inner[i].node = node;
    key[i] = nearest;
}

/* popNodePacket, which also gives the entry distances of the node it returns. */
static inline int packetPopNode(BvhStackPacket* stack, PacketFloat limit, PacketFloat* entry) {
    int node = popNodePacket(stack, limit);
    if (node >= 0) *entry = stack->entries[stack->top].entry; /* the entry just popped */
    return node;
}

/* As nextNode: descend into the nearest inner child still entered by some ray by
 * `childLimit`, push the others (the farthest deepest), or resume from the stack, skipping
 * the nodes that no ray enters by `stackLimit`; -1 when the walk is over or its stack
 * overflowed (stack->overflowed). *entry receives the next node's entry distances. */
static inline int packetNextNode(const BvhStackEntryPacket* inner, int count, BvhStackPacket* stack,
                                 PacketFloat childLimit, PacketFloat stackLimit, PacketFloat* entry) {
    int chosen = -1;
    for (int i = 0; i < count; ++i) {
        if (!packetAny(enteredByPacket(inner[i].entry, childLimit))) continue;
        if (chosen >= 0 && !pushNodePacket(stack, inner[chosen].node, inner[chosen].entry)) return -1;
        chosen = i;
    }
    if (chosen < 0) return packetPopNode(stack, stackLimit, entry);
    *entry = inner[chosen].entry;
    return inner[chosen].node;
}

/* The packet's mesh walk holds as many nodes as a ray's (RAY_BVH_SHORT_STACK, which the
 * tests shrink to make it overflow). */
#define RAY_PACKET_MESH_STACK RAY_BVH_SHORT_STACK

/* The number of rays of the packet that enter a node, at or below which they walk on
 * through it each alone. Near the leaves of a dense mesh, a packet's rays part for
 * different triangles, and a box or triangle tested for the whole packet serves one or two:
 * one ray's walk (a node's four children in one float4 slab test, a triangle in scalar code
 * that leaves at its first failed test) is then cheaper, as in Embree's hybrid packets. */
#ifndef RAY_PACKET_MESH_ALONE
#define RAY_PACKET_MESH_ALONE 1
#endif

/* Asks the CPU to fetch the cache line of p ahead of its use. */
#define packetPrefetch(p) __builtin_prefetch((const void*)(size_t)(p))

/* The number of lanes set in mask m. */
static inline int packetCount(PacketInt m) {
#if __has_builtin(__builtin_reduce_add)
    return -__builtin_reduce_add(m);
#else
    PacketIntLanes lanes = {m};
    int n = 0;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) n -= lanes.lane[l];
    return n;
#endif
}

/* The distance beyond which the mesh walk skips a box, a lane a ray: the nearest hit so far;
 * with anyHit, a ray that hit a triangle is done (-1). */
static inline PacketFloat meshPrune(const TriangleHitPacket* h, bool anyHit) {
    return anyHit ? select(h->best, (PacketFloat)(-1.0f), h->part >= (PacketInt)(0)) : h->best;
}

/* The rays of `lanes` search the subtree under `node` each alone (intersectMesh), going on
 * from where their searches in h stand: the tie rule makes the triangle found the same. */
static void walkMeshLanesAlone(__global const RayWideBvhNode* nodes, __global const RayTriangle4* triangles, int node,
                               const PacketRays* r, PacketInt lanes, BvhStackEntry* spare, TriangleHitPacket* h) {
    int take[RAY_PACKET_WIDTH], part[RAY_PACKET_WIDTH];
    float best[RAY_PACKET_WIDTH], b1[RAY_PACKET_WIDTH], b2[RAY_PACKET_WIDTH];
    float ox[RAY_PACKET_WIDTH], oy[RAY_PACKET_WIDTH], oz[RAY_PACKET_WIDTH];
    float dx[RAY_PACKET_WIDTH], dy[RAY_PACKET_WIDTH], dz[RAY_PACKET_WIDTH];
    RAY_PACKET_STORE(lanes, take);
    RAY_PACKET_STORE(h->best, best);
    RAY_PACKET_STORE(h->part, part);
    RAY_PACKET_STORE(h->b1, b1);
    RAY_PACKET_STORE(h->b2, b2);
    RAY_PACKET_STORE(r->origin.x, ox);
    RAY_PACKET_STORE(r->origin.y, oy);
    RAY_PACKET_STORE(r->origin.z, oz);
    RAY_PACKET_STORE(r->direction.x, dx);
    RAY_PACKET_STORE(r->direction.y, dy);
    RAY_PACKET_STORE(r->direction.z, dz);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        if (!take[l]) continue;
        TriangleHit one = {best[l], part[l], b1[l], b2[l]};
        intersectMesh(nodes, triangles, node, (float3)(ox[l], oy[l], oz[l]), (float3)(dx[l], dy[l], dz[l]), spare,
                      RAY_BVH_SHORT_STACK, &one);
        best[l] = one.best;
        part[l] = one.part;
        b1[l] = one.b1;
        b2[l] = one.b2;
    }
    h->best = RAY_PACKET_LOAD(best);
    h->part = RAY_PACKET_LOAD(part);
    h->b1 = RAY_PACKET_LOAD(b1);
    h->b2 = RAY_PACKET_LOAD(b2);
}

/* intersectMesh for a packet: the mesh's own tree (from `root`) walked by every ray of the
 * packet at once, as the scene's (traceBvhPacket), in object space (r), a leaf's triangles
 * tested for every ray at once, until few rays enter a node (RAY_PACKET_MESH_ALONE). The
 * triangle's tie rule (intersectTriangle) makes each ray's triangle the one its own walk
 * finds, whatever the order of the packet's. With anyHit, a ray stops at its first triangle
 * (a shadow ray asks only whether something blocks it). `spare`: RAY_BVH_SHORT_STACK entries
 * for the walks alone. */
static inline void packetWalkMesh(__global const RayWideBvhNode* nodes, __global const RayTriangle4* triangles, int root,
                                  const PacketRays* r, bool anyHit, BvhStackEntry* spare, TriangleHitPacket* h) {
    BvhStackEntryPacket entries[RAY_PACKET_MESH_STACK];
    BvhStackPacket stack = emptyBvhStackPacket(entries, RAY_PACKET_MESH_STACK);
    int next = root;
    PacketFloat nextEntry = (PacketFloat)(0.0f);
    while (next >= 0) {
        PacketFloat limit = meshPrune(h, anyHit);
        const PacketInt active = enteredByPacket(nextEntry, limit);
        if (packetCount(active) <= RAY_PACKET_MESH_ALONE) {
            walkMeshLanesAlone(nodes, triangles, next, r, active, spare, h);
            next = packetPopNode(&stack, meshPrune(h, anyHit), &nextEntry);
            continue;
        }
        /* The rays that do not enter the node test none of its children. */
        limit = select((PacketFloat)(-1.0f), limit, active);
        __global const RayWideBvhNode* node = &nodes[next];
        BvhStackEntryPacket inner[4];
        float key[4];
        int innerCount = 0;
        for (int c = 0; c < 4; ++c) {
            const int index = ((__global const int*)&node->index)[c];
            if (index < 0) break;
            const int count = ((__global const int*)&node->count)[c];
            if (count > 0) {
                __global const char* record = (__global const char*)&triangles[index >> 2];
                packetPrefetch(record);
                packetPrefetch(record + 64);
                packetPrefetch(record + 128);
            } else {
                packetPrefetch(&nodes[index]);
                packetPrefetch((__global const char*)&nodes[index] + 64);
            }
        }
        for (int c = 0; c < 4; ++c) {
            const int index = ((__global const int*)&node->index)[c];
            if (index < 0) continue;
            PacketFloat entry = packetChildEntry(node, c, r, limit);
            if (!packetAny(enteredByPacket(entry, limit))) continue;
            const int count = ((__global const int*)&node->count)[c];
            if (count > 0) {
                intersectTriangleSlotsPacket(triangles, index, count, r->origin, r->direction, h);
                limit = select((PacketFloat)(-1.0f), meshPrune(h, anyHit), active);
            } else {
                addInnerPacket(inner, key, &innerCount, index, entry, anyHit ? 0.0f : packetMinimum(entry));
            }
        }
        next = packetNextNode(inner, innerCount, &stack, limit, meshPrune(h, anyHit), &nextEntry);
    }
    if (!stack.overflowed) return;
    /* As a ray's walk does on overflow (afterOverflow): every triangle under the root. */
    int2 range = leafRange(nodes, root);
    intersectTriangleSlotsPacket(triangles, range.x, range.y - range.x, r->origin, r->direction, h);
}

/* intersectPrimitive for the rays of `entering` and one mesh primitive (not under
 * courseMeshes, no motion: the caller leaves those to intersectPrimitive). */
static inline void packetIntersectMesh(__global const RayWideBvhNode* nodes, __global const RayTriangle4* triangles,
                                       __global const RayPrimitive* prim, int index, const PacketRays* r,
                                       PacketInt entering, bool anyHit, BvhStackEntry* spare, PacketHitKeys* keys,
                                       Hit* hits) {
    PacketRays object;
    object.origin = transformPointPacket(prim->worldToObject, r->origin);
    object.direction = transformVectorPacket(prim->worldToObject, r->direction);
    object.inverse = safeInversePacket(object.direction);
    const int order = prim->order;
    PacketFloat limit = hitLimitPacket(keys->t.vector, keys->primitive.vector, keys->order.vector, order);
    TriangleHitPacket h = {select((PacketFloat)(-1.0f), limit, entering), (PacketInt)(-1), (PacketFloat)(0.0f),
                           (PacketFloat)(0.0f)};
    packetWalkMesh(nodes, triangles, prim->geometry, &object, anyHit, spare, &h);
    PacketInt better = h.part >= (PacketInt)(0); /* below limit: a triangle at limit itself loses (index < -1) */
    if (!packetAny(better)) return;
    int take[RAY_PACKET_WIDTH], part[RAY_PACKET_WIDTH];
    float t[RAY_PACKET_WIDTH], b1[RAY_PACKET_WIDTH], b2[RAY_PACKET_WIDTH];
    float px[RAY_PACKET_WIDTH], py[RAY_PACKET_WIDTH], pz[RAY_PACKET_WIDTH];
    RAY_PACKET_STORE(better, take);
    RAY_PACKET_STORE(h.part, part);
    RAY_PACKET_STORE(h.best, t);
    RAY_PACKET_STORE(h.b1, b1);
    RAY_PACKET_STORE(h.b2, b2);
    RAY_PACKET_STORE(object.origin.x + h.best * object.direction.x, px); /* o + best * d */
    RAY_PACKET_STORE(object.origin.y + h.best * object.direction.y, py);
    RAY_PACKET_STORE(object.origin.z + h.best * object.direction.z, pz);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        if (!take[l]) continue;
        takeHit(&hits[l], t[l], index, order, part[l], (float3)(px[l], py[l], pz[l]),
                triangleFaceNormal(triangles, part[l]), (float2)(b1[l], b2[l]));
    }
    keepPacketKeys(keys, h.best, index, order, better);
}

/* Intersects the primitives [first, first + count) for the rays of `entering`, then brings
 * their limits up to date; with anyHit a ray that hit something is done. The convex shapes
 * and meshes are tested for every ray at once unless rays move (motion blur), meshes also
 * unless their hits are keyed by the course's distance (courseMeshes); the others ray by
 * ray. */
static inline void packetLeaf(__global const RayWideBvhNode* nodes, __global const RayPrimitive* prims,
                              __global const RayTriangle4* triangles, __global const float4* motions,
                              const Ray* rays, const PacketRays* packet, bool moving, PacketInt entering, int first,
                              int count, bool anyHit, bool courseMeshes, BvhStackEntry* spare, Hit* hits,
                              PacketHitKeys* keys, PacketLanes* limits) {
    int lanes[RAY_PACKET_WIDTH];
    bool lanesStored = false; /* lanes holds `entering`, for the primitives tested ray by ray */
    for (int i = first; i < first + count; ++i) {
        if (!moving && convexShape(prims[i].type)) {
            packetIntersectPrimitive(&prims[i], i, packet, entering, keys, hits);
            continue;
        }
        if (!moving && !courseMeshes && prims[i].type == RAY_PRIM_MESH) {
            packetIntersectMesh(nodes, triangles, &prims[i], i, packet, entering, anyHit, spare, keys, hits);
            continue;
        }
        if (!lanesStored) RAY_PACKET_STORE(entering, lanes);
        lanesStored = true;
        for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
            if (!lanes[l]) continue;
            intersectPrimitive(nodes, triangles, motions, &prims[i], i, rays[l], courseMeshes, spare,
                               RAY_BVH_SHORT_STACK, &hits[l]);
            keepHitKeys(keys, l, &hits[l]);
        }
    }
    PacketFloat prune = courseMeshes ? (PacketFloat)(RAY_INFINITY) : keys->t.vector; /* pruneDistance */
    if (anyHit) prune = select(prune, (PacketFloat)(-1.0f), keys->primitive.vector >= (PacketInt)(0));
    limits->vector = select(limits->vector, prune, entering);
}

/* traceBvh for the rays of `lanes` (non-zero: trace it) at once, each below its own tMax:
 * hits[l] as traceBvh(rays[l], tMax[l], ...) gives it; lanes not traced keep hits[l] as
 * they were. The children of a node are visited nearest first for the packet's nearest ray
 * (closest hits), or in node order (anyHit). */
RAY_CALL_ON_CPU void traceBvhPacket(__global const RayWideBvhNode* nodes, __global const RayCpuBvhNode* cpuNodes,
                                     __global const RayPrimitive* prims, __global const RayTriangle4* triangles,
                                     __global const float4* motions,
                                     const Ray* rays, const float* tMax, const int* lanes, bool anyHit,
                                     bool courseMeshes, Hit* hits) {
    /* the lanes' state set up in vectors: the start of every walk, and a shadow packet's
     * walk is short */
    float times[RAY_PACKET_WIDTH];
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        times[l] = rays[l].time;
        if (!lanes[l]) continue;
        hits[l].t = tMax[l];
        hits[l].primitive = -1;
        hits[l].order = 0;
    }
    const PacketInt traced = RAY_PACKET_LOAD(lanes) != (PacketInt)(0);
    const PacketFloat t = RAY_PACKET_LOAD(tMax);
    const bool moving = packetAny(traced & (RAY_PACKET_LOAD(times) != (PacketFloat)(0.0f)));
    PacketLanes limits;
    PacketHitKeys keys;
    limits.vector = select((PacketFloat)(-1.0f), courseMeshes ? (PacketFloat)(RAY_INFINITY) : t, traced);
    keys.t.vector = select((PacketFloat)(-1.0f), t, traced);
    keys.primitive.vector = (PacketInt)(-1);
    keys.order.vector = (PacketInt)(0);
    const PacketRays packet = packetRays(rays);
    BvhStackEntry spare[RAY_BVH_SHORT_STACK]; /* the mesh walks' (intersectMesh) */
    BvhStackEntryPacket entries[RAY_PACKET_STACK];
    BvhStackPacket stack = emptyBvhStackPacket(entries, RAY_PACKET_STACK);
    int next = 0;
    PacketFloat nextEntry; /* the next node's entry distances, which this walk does not use */
    while (next >= 0) {
        __global const RayWideBvhNode* node = &nodes[next];
        /* the inner children entered, nearest (for the packet's nearest ray) last */
        BvhStackEntryPacket inner[4];
        float key[4];
        int innerCount = 0;
        for (int c = 0; c < 4; ++c) {
            const int index = ((__global const int*)&node->index)[c];
            if (index < 0) continue;
            PacketFloat entry = packetChildEntry(node, c, &packet, limits.vector);
            PacketInt entering = enteredByPacket(entry, limits.vector);
            if (!packetAny(entering)) continue;
            const int count = ((__global const int*)&node->count)[c];
            if (count > 0) {
                packetLeaf(nodes, prims, triangles, motions, rays, &packet, moving, entering, index, count, anyHit,
                           courseMeshes, spare, hits, &keys, &limits);
                continue;
            }
            addInnerPacket(inner, key, &innerCount, index, entry, anyHit ? 0.0f : packetMinimum(entry));
        }
        next = packetNextNode(inner, innerCount, &stack, limits.vector, limits.vector, &nextEntry);
    }
    if (!stack.overflowed) return;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l)
        if (lanes[l])
            traceBvh(nodes, cpuNodes, prims, triangles, motions, rays[l], tMax[l], anyHit, courseMeshes, &hits[l]);
}

#endif /* RAY_PACKET_WIDTH */
