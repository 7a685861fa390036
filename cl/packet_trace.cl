/* The packet walk: RAY_PACKET_WIDTH rays through the scene's BVH at once, for CPU devices
 * (cl/packet_render.cl). Built only in a packet build (a CPU device's: cl/device/variant.h);
 * GPUs never see it.
 *
 * Why: PoCL runs traceBvh, one ray per work-item, as scalar code (its control flow is too
 * divergent to vectorise across work-items), so a CPU's 8- or 16-wide vector units idle.
 * Here a node's box is tested for every ray of the packet in one floatN slab test, and the
 * walk descends into a child while any ray of the packet enters it. A leaf's primitives are
 * intersected for the rays that enter its box within their nearest hit so far: cubes,
 * spheres, cylinders and cones for those rays at once (packetIntersectPrimitive: the
 * single-ray intersectors' operations in floatN), the others ray by ray with the single-ray
 * walk's own intersectPrimitive. Every ray gets exactly the hit traceBvh gives it (hits are
 * ranked by distance and then by order, Hit.order, whatever the order in which they are
 * found), so the images are the single-ray path's to the bit.
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
#else
typedef float4 PacketFloat;
typedef int4 PacketInt;
#define RAY_PACKET_LOAD(pointer) vload4(0, pointer)
#define RAY_PACKET_STORE(value, pointer) vstore4(value, 0, pointer)
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

/* The rays of a packet as the box tests and the shape tests read them: origins, safe
 * inverse directions (safeInverse) and directions, one vector a coordinate. */
typedef struct {
    PacketFloat originX, originY, originZ;
    PacketFloat inverseX, inverseY, inverseZ;
    PacketFloat directionX, directionY, directionZ;
} PacketRays;

static inline PacketRays packetRays(const Ray* rays) {
    float ox[RAY_PACKET_WIDTH], oy[RAY_PACKET_WIDTH], oz[RAY_PACKET_WIDTH];
    float ix[RAY_PACKET_WIDTH], iy[RAY_PACKET_WIDTH], iz[RAY_PACKET_WIDTH];
    float dx[RAY_PACKET_WIDTH], dy[RAY_PACKET_WIDTH], dz[RAY_PACKET_WIDTH];
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        float3 inverse = safeInverse(rays[l].direction);
        ox[l] = rays[l].origin.x;
        oy[l] = rays[l].origin.y;
        oz[l] = rays[l].origin.z;
        ix[l] = inverse.x;
        iy[l] = inverse.y;
        iz[l] = inverse.z;
        dx[l] = rays[l].direction.x;
        dy[l] = rays[l].direction.y;
        dz[l] = rays[l].direction.z;
    }
    PacketRays p = {RAY_PACKET_LOAD(ox), RAY_PACKET_LOAD(oy), RAY_PACKET_LOAD(oz),
                    RAY_PACKET_LOAD(ix), RAY_PACKET_LOAD(iy), RAY_PACKET_LOAD(iz),
                    RAY_PACKET_LOAD(dx), RAY_PACKET_LOAD(dy), RAY_PACKET_LOAD(dz)};
    return p;
}

/* Minimum and maximum of operands that are never NaN, as one select each (see
 * RAY_DEFINE_CHILD_ENTRY_DISTANCES, cl/intersect.cl). */
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

/* The unit shapes of cl/intersect.cl for every ray of a packet at once: the same
 * operations, in the same order and grouping, a lane a ray, so that each lane's answer is
 * the single-ray intersector's to the bit (tests/cpu_paths.sh). A lane whose search is not
 * to change starts with a negative best (considerHit takes only 0 < t < best). */
typedef struct {
    PacketFloat best; /* the nearest t so far, as intersectCube's *best */
    PacketInt part;
    PacketFloat normalX, normalY, normalZ;
} PacketShapeHit;

/* dot(a, b) of float3s, a lane a pair: PoCL's dot is ((a.x·b.x + a.y·b.y) + a.z·b.z) with
 * no fused multiply-add, where OpenCL C would fuse this expression written out (measured:
 * a third of the results differ in the last bit). */
static inline PacketFloat packetDot(PacketFloat ax, PacketFloat ay, PacketFloat az, PacketFloat bx, PacketFloat by,
                                    PacketFloat bz) {
#pragma OPENCL FP_CONTRACT OFF
    return ax * bx + ay * by + az * bz;
}

/* considerHit, for the lanes of `candidate` (true: a hit of this shape at t). */
static inline void packetConsiderHit(PacketInt candidate, PacketFloat t, PacketInt part, PacketFloat nx,
                                     PacketFloat ny, PacketFloat nz, PacketShapeHit* h) {
    PacketInt take = candidate & (t > (PacketFloat)(0.0f)) & (t < h->best);
    h->best = select(h->best, t, take);
    h->part = select(h->part, part, take);
    h->normalX = select(h->normalX, nx, take);
    h->normalY = select(h->normalY, ny, take);
    h->normalZ = select(h->normalZ, nz, take);
}

/* closestApproachRoots: the lanes that have roots, and the roots. */
static inline PacketInt packetClosestApproachRoots(PacketFloat a, PacketFloat halfB, PacketFloat c,
                                                   PacketFloat discriminant, PacketFloat* t0, PacketFloat* t1) {
    PacketInt found = (discriminant >= (PacketFloat)(0.0f)) & (a != (PacketFloat)(0.0f));
    PacketFloat q = -(halfB + copysign(sqrt(discriminant), halfB));
    PacketFloat r0 = q / a;
    PacketFloat r1 = select(r0, c / q, q != (PacketFloat)(0.0f));
    *t0 = fmin(r0, r1);
    *t1 = fmax(r0, r1);
    return found;
}

static inline void packetIntersectSphere(PacketFloat ox, PacketFloat oy, PacketFloat oz, PacketFloat dx,
                                         PacketFloat dy, PacketFloat dz, PacketShapeHit* h) {
    PacketFloat a = packetDot(dx, dy, dz, dx, dy, dz), halfB = packetDot(ox, oy, oz, dx, dy, dz);
    PacketFloat s = halfB / a;
    PacketFloat fx = ox - s * dx, fy = oy - s * dy, fz = oz - s * dz;
    PacketFloat t0, t1;
    PacketInt found = packetClosestApproachRoots(a, halfB, packetDot(ox, oy, oz, ox, oy, oz) - 0.25f,
                                                 a * (0.25f - packetDot(fx, fy, fz, fx, fy, fz)), &t0, &t1);
    PacketFloat t = select(t1, t0, t0 > (PacketFloat)(0.0f));
    packetConsiderHit(found, t, (PacketInt)(PART_SIDE), ox + t * dx, oy + t * dy, oz + t * dz, h);
}

/* intersectCap: a cap of radius 0.5 in the plane y = capY. */
static inline void packetIntersectCap(PacketFloat ox, PacketFloat oy, PacketFloat oz, PacketFloat dx, PacketFloat dy,
                                      PacketFloat dz, float capY, int capPart, PacketShapeHit* h) {
    PacketFloat t = (capY - oy) / dy;
    PacketFloat px = ox + t * dx, pz = oz + t * dz;
    PacketInt inside = (dy != (PacketFloat)(0.0f)) & (px * px + pz * pz <= (PacketFloat)(0.25f));
    packetConsiderHit(inside, t, (PacketInt)(capPart), (PacketFloat)(0.0f), (PacketFloat)(capY > 0.0f ? 1.0f : -1.0f),
                      (PacketFloat)(0.0f), h);
}

/* considerSideRoot: a root of the side surface counts between the caps. */
static inline void packetConsiderSideRoot(PacketInt found, PacketFloat ox, PacketFloat oy, PacketFloat oz,
                                          PacketFloat dx, PacketFloat dy, PacketFloat dz, PacketFloat t, bool cone,
                                          PacketShapeHit* h) {
    PacketFloat px = ox + t * dx, py = oy + t * dy, pz = oz + t * dz;
    PacketInt between = found & (py >= (PacketFloat)(-0.5f)) & (py <= (PacketFloat)(0.5f));
    PacketFloat ny = cone ? 0.25f * (0.5f - py) : (PacketFloat)(0.0f);
    packetConsiderHit(between, t, (PacketInt)(PART_SIDE), px, ny, pz, h);
}

static inline void packetIntersectCylinder(PacketFloat ox, PacketFloat oy, PacketFloat oz, PacketFloat dx,
                                           PacketFloat dy, PacketFloat dz, PacketShapeHit* h) {
    PacketFloat a = dx * dx + dz * dz;
    PacketFloat halfB = ox * dx + oz * dz;
    PacketFloat fx = ox - (halfB / a) * dx, fz = oz - (halfB / a) * dz;
    PacketFloat t0, t1;
    PacketInt found = (a > (PacketFloat)(0.0f)) &
                      packetClosestApproachRoots(a, halfB, ox * ox + oz * oz - 0.25f,
                                                 a * (0.25f - (fx * fx + fz * fz)), &t0, &t1);
    packetConsiderSideRoot(found, ox, oy, oz, dx, dy, dz, t0, false, h);
    packetConsiderSideRoot(found, ox, oy, oz, dx, dy, dz, t1, false, h);
    packetIntersectCap(ox, oy, oz, dx, dy, dz, 0.5f, PART_TOP, h);
    packetIntersectCap(ox, oy, oz, dx, dy, dz, -0.5f, PART_BOTTOM, h);
}

static inline void packetIntersectCone(PacketFloat ox, PacketFloat oy, PacketFloat oz, PacketFloat dx,
                                       PacketFloat dy, PacketFloat dz, PacketShapeHit* h) {
    PacketFloat k = 0.5f - oy;
    PacketFloat a = dx * dx + dz * dz - 0.25f * dy * dy;
    PacketFloat b = 2.0f * (ox * dx + oz * dz) + 0.5f * k * dy;
    PacketFloat c = ox * ox + oz * oz - 0.25f * k * k;
    /* solveQuadratic: a linear equation where a is 0 */
    PacketInt linear = a == (PacketFloat)(0.0f);
    PacketFloat halfB = 0.5f * b;
    PacketFloat t0, t1;
    PacketInt found = packetClosestApproachRoots(a, halfB, c, halfB * halfB - a * c, &t0, &t1);
    PacketFloat root = -c / b;
    t0 = select(t0, root, linear);
    t1 = select(t1, root, linear);
    found = select(found, b != (PacketFloat)(0.0f), linear);
    packetConsiderSideRoot(found, ox, oy, oz, dx, dy, dz, t0, true, h);
    packetConsiderSideRoot(found, ox, oy, oz, dx, dy, dz, t1, true, h);
    packetIntersectCap(ox, oy, oz, dx, dy, dz, -0.5f, PART_BOTTOM, h);
}

/* intersectCube's slabs, one axis: the lanes that miss (parallel and outside), and the
 * entering and leaving distances and faces. */
static inline PacketInt packetCubeSlab(PacketFloat oa, PacketFloat da, int axis, PacketFloat* tEnter,
                                       PacketInt* enterFace, PacketFloat* tLeave, PacketInt* leaveFace) {
    PacketInt parallel = da == (PacketFloat)(0.0f);
    PacketInt outside = parallel & ((oa < (PacketFloat)(-0.5f)) | (oa > (PacketFloat)(0.5f)));
    PacketFloat inverse = 1.0f / da;
    PacketFloat tLow = (-0.5f - oa) * inverse, tHigh = (0.5f - oa) * inverse;
    PacketInt swap = tLow > tHigh;
    PacketFloat low = select(tLow, tHigh, swap), high = select(tHigh, tLow, swap);
    PacketInt lowFace = select((PacketInt)(axis * 2 + 1), (PacketInt)(axis * 2), swap);
    PacketInt highFace = select((PacketInt)(axis * 2), (PacketInt)(axis * 2 + 1), swap);
    PacketInt enters = ~parallel & (low > *tEnter), leaves = ~parallel & (high < *tLeave);
    *tEnter = select(*tEnter, low, enters);
    *enterFace = select(*enterFace, lowFace, enters);
    *tLeave = select(*tLeave, high, leaves);
    *leaveFace = select(*leaveFace, highFace, leaves);
    return outside;
}

static inline void packetIntersectCube(PacketFloat ox, PacketFloat oy, PacketFloat oz, PacketFloat dx,
                                       PacketFloat dy, PacketFloat dz, PacketShapeHit* h) {
    PacketFloat tEnter = (PacketFloat)(-RAY_INFINITY), tLeave = (PacketFloat)(RAY_INFINITY);
    PacketInt enterFace = (PacketInt)(0), leaveFace = (PacketInt)(0);
    PacketInt missed = packetCubeSlab(ox, dx, 0, &tEnter, &enterFace, &tLeave, &leaveFace);
    missed |= packetCubeSlab(oy, dy, 1, &tEnter, &enterFace, &tLeave, &leaveFace);
    missed |= packetCubeSlab(oz, dz, 2, &tEnter, &enterFace, &tLeave, &leaveFace);
    PacketInt fromOutside = tEnter > (PacketFloat)(0.0f);
    PacketFloat t = select(tLeave, tEnter, fromOutside);
    PacketInt face = select(leaveFace, enterFace, fromOutside);
    PacketFloat sign = select((PacketFloat)(1.0f), (PacketFloat)(-1.0f), (face & 1) != 0);
    PacketFloat zero = (PacketFloat)(0.0f);
    PacketFloat nx = select(zero, sign, face < 2), ny = select(zero, sign, (face >= 2) & (face < 4)),
                nz = select(zero, sign, face >= 4);
    packetConsiderHit(~missed & ~(tEnter > tLeave), t, face, nx, ny, nz, h);
}

/* Whether a primitive of this type has a packet intersector (the others, the torus, meshes
 * and csg objects, are intersected ray by ray). */
static inline bool packetShape(int type) {
    return type == RAY_PRIM_CUBE || type == RAY_PRIM_SPHERE || type == RAY_PRIM_CYLINDER || type == RAY_PRIM_CONE;
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

/* intersectPrimitive for the rays of `entering` and one primitive of a type packetShape
 * takes, the rays carried into its object space in vectors; hits[l] changes as
 * intersectPrimitive changes it (no motion: the caller leaves moving rays to it). */
static inline void packetIntersectPrimitive(__global const RayPrimitive* prim, int index, const PacketRays* r,
                                            PacketInt entering, PacketHitKeys* keys, Hit* hits) {
    __global const float4* m = prim->worldToObject;
    /* transformPoint and transformVector */
#define RAY_ROW_DOT(row, vx, vy, vz) packetDot((PacketFloat)(m[row].x), (PacketFloat)(m[row].y), (PacketFloat)(m[row].z), vx, vy, vz)
    PacketFloat ox = RAY_ROW_DOT(0, r->originX, r->originY, r->originZ) + m[0].w;
    PacketFloat oy = RAY_ROW_DOT(1, r->originX, r->originY, r->originZ) + m[1].w;
    PacketFloat oz = RAY_ROW_DOT(2, r->originX, r->originY, r->originZ) + m[2].w;
    PacketFloat dx = RAY_ROW_DOT(0, r->directionX, r->directionY, r->directionZ);
    PacketFloat dy = RAY_ROW_DOT(1, r->directionX, r->directionY, r->directionZ);
    PacketFloat dz = RAY_ROW_DOT(2, r->directionX, r->directionY, r->directionZ);
#undef RAY_ROW_DOT
    /* a primitive listed after the one hit so far also takes a hit at exactly its t */
    const int order = prim->info.z;
    PacketInt winsTies = (keys->primitive.vector >= (PacketInt)(0)) & ((PacketInt)(order) > keys->order.vector);
    PacketFloat limit = select(keys->t.vector, nextafter(keys->t.vector, (PacketFloat)(RAY_INFINITY)), winsTies);
    PacketShapeHit h = {select((PacketFloat)(-1.0f), limit, entering), (PacketInt)(0), (PacketFloat)(0.0f),
                        (PacketFloat)(0.0f), (PacketFloat)(0.0f)};
    switch (prim->info.x) {
        case RAY_PRIM_CUBE: packetIntersectCube(ox, oy, oz, dx, dy, dz, &h); break;
        case RAY_PRIM_SPHERE: packetIntersectSphere(ox, oy, oz, dx, dy, dz, &h); break;
        case RAY_PRIM_CYLINDER: packetIntersectCylinder(ox, oy, oz, dx, dy, dz, &h); break;
        default: packetIntersectCone(ox, oy, oz, dx, dy, dz, &h); break;
    }
    PacketInt better = entering & (h.best < limit);
    if (!any(better)) return;
    int take[RAY_PACKET_WIDTH], part[RAY_PACKET_WIDTH];
    float t[RAY_PACKET_WIDTH], px[RAY_PACKET_WIDTH], py[RAY_PACKET_WIDTH], pz[RAY_PACKET_WIDTH];
    float nx[RAY_PACKET_WIDTH], ny[RAY_PACKET_WIDTH], nz[RAY_PACKET_WIDTH];
    RAY_PACKET_STORE(better, take);
    RAY_PACKET_STORE(h.part, part);
    RAY_PACKET_STORE(h.best, t);
    RAY_PACKET_STORE(ox + h.best * dx, px); /* o + best * d */
    RAY_PACKET_STORE(oy + h.best * dy, py);
    RAY_PACKET_STORE(oz + h.best * dz, pz);
    RAY_PACKET_STORE(h.normalX, nx);
    RAY_PACKET_STORE(h.normalY, ny);
    RAY_PACKET_STORE(h.normalZ, nz);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        if (!take[l]) continue;
        Hit* hit = &hits[l];
        hit->t = t[l];
        hit->primitive = index;
        hit->order = order;
        hit->part = part[l];
        hit->objectPoint = (float3)(px[l], py[l], pz[l]);
        hit->objectNormal = (float3)(nx[l], ny[l], nz[l]);
        hit->barycentric = (float2)(0.0f);
    }
    keys->t.vector = select(keys->t.vector, h.best, better);
    keys->primitive.vector = select(keys->primitive.vector, (PacketInt)(index), better);
    keys->order.vector = select(keys->order.vector, (PacketInt)(order), better);
}

/* Intersects the primitives [first, first + count) for the rays of `entering`, then brings
 * their limits up to date; with anyHit a ray that hit something is done. The shapes with a
 * packet intersector are tested for every ray at once unless rays move (motion blur);
 * the others ray by ray. */
static inline void packetLeaf(__global const RayWideBvhNode* nodes, __global const RayPrimitive* prims,
                              __global const RayTriangle* triangles, __global const float4* motions,
                              const Ray* rays, const PacketRays* packet, bool moving, PacketInt entering, int first,
                              int count, bool anyHit, bool courseMeshes, BvhStackEntry* spare, Hit* hits,
                              PacketHitKeys* keys, PacketLanes* limits) {
    int lanes[RAY_PACKET_WIDTH];
    bool lanesStored = false; /* lanes holds `entering`, for the primitives tested ray by ray */
    for (int i = first; i < first + count; ++i) {
        if (!moving && packetShape(prims[i].info.x)) {
            packetIntersectPrimitive(&prims[i], i, packet, entering, keys, hits);
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
                                     __global const RayPrimitive* prims, __global const RayTriangle* triangles,
                                     __global const float4* motions,
                                     const Ray* rays, const float* tMax, const int* lanes, bool anyHit,
                                     bool courseMeshes, Hit* hits) {
    PacketLanes limits;
    PacketHitKeys keys;
    bool moving = false;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        limits.lane[l] = -1.0f;
        keys.t.lane[l] = -1.0f;
        keys.primitive.lane[l] = -1;
        keys.order.lane[l] = 0;
        if (!lanes[l]) continue;
        hits[l].t = tMax[l];
        hits[l].primitive = -1;
        hits[l].order = 0;
        keepHitKeys(&keys, l, &hits[l]);
        limits.lane[l] = courseMeshes ? RAY_INFINITY : tMax[l];
        moving |= rays[l].time != 0.0f;
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
                packetLeaf(nodes, prims, triangles, motions, rays, &packet, moving, entering, index, count, anyHit,
                           courseMeshes, spare, hits, &keys, &limits);
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
        if (lanes[l])
            traceBvh(nodes, cpuNodes, prims, triangles, motions, rays[l], tMax[l], anyHit, courseMeshes, &hits[l]);
}

#endif /* RAY_PACKET_WIDTH */
