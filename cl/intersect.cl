/* Ray–primitive intersection and BVH traversal.
 *
 * Primitives are intersected in object space: the world ray is carried into the unit
 * primitive's space by its world-to-object transform without renormalizing the direction,
 * so the parameter t means the same distance along the ray in both spaces and hits of
 * different primitives compare directly.
 *
 * No fast-math here: the slab tests rely on IEEE infinities. */

#define RAY_INFINITY INFINITY

typedef struct {
    float3 origin;
    float3 direction; /* unit length in world space */
    float time;       /* shutter time of the ray's camera sample (motion blur); 0: the scene at rest */
} Ray;

/* Which part of a primitive was hit; decides the texture mapping (SPEC §5). */
#define PART_SIDE 0
#define PART_TOP 1    /* +y cap (cylinder) */
#define PART_BOTTOM 2 /* -y cap (cylinder, cone) */
/* Cube faces: 0..5 = +x, -x, +y, -y, +z, -z. */

typedef struct {
    float t;
    int primitive;   /* position in the primitive buffer, -1 for a miss */
    int part;
    float3 objectPoint;
    float3 objectNormal; /* outward, unnormalized */
    float2 barycentric;  /* meshes: the weights of the triangle's corners 1 and 2 (part: the triangle) */
    int order;           /* the hit primitive's info.z: exact ties go to the higher (cl/shared_types.h) */
} Hit;

static inline float3 transformPoint(__global const float4* m, float3 p) {
    return (float3)(dot(m[0].xyz, p) + m[0].w, dot(m[1].xyz, p) + m[1].w, dot(m[2].xyz, p) + m[2].w);
}

static inline float3 transformVector(__global const float4* m, float3 v) {
    return (float3)(dot(m[0].xyz, v), dot(m[1].xyz, v), dot(m[2].xyz, v));
}

/* Object normal to world: the transpose of world-to-object's linear part (SPEC §1: normals
 * transform by the inverse transpose of object-to-world). */
static inline float3 normalToWorld(__global const float4* m, float3 n) {
    return normalize(m[0].xyz * n.x + m[1].xyz * n.y + m[2].xyz * n.z);
}

/* The roots of a t² + 2·halfB·t + c = 0, ascending, given its quarter discriminant
 * halfB² − a·c; false when there are none. The sphere and the cylinder compute that
 * discriminant from the ray's closest approach to the centre or axis, a·(r² − |f|²): the
 * schoolbook b² − 4ac cancels catastrophically in float when the shape is small against
 * its distance (the tiny spheres of recursiveSpheres*.xml, whose object-space origins are
 * thousands of radii away), that form does not. The roots come from q and c/q, without
 * a second cancellation (host/reference/shapes.cpp does the same). */
static inline bool closestApproachRoots(float a, float halfB, float c, float discriminant, float* t0, float* t1) {
    if (!(discriminant >= 0.0f) || a == 0.0f) return false;
    float q = -(halfB + copysign(sqrt(discriminant), halfB));
    float r0 = q / a;
    float r1 = q != 0.0f ? c / q : r0;
    *t0 = fmin(r0, r1);
    *t1 = fmax(r0, r1);
    return true;
}

/* Both roots of a t² + b t + c = 0 in ascending order (the cone's, whose a may be 0: then
 * the one root of the linear equation); false when there are none. */
static inline bool solveQuadratic(float a, float b, float c, float* t0, float* t1) {
    if (a == 0.0f) {
        if (b == 0.0f) return false;
        *t0 = *t1 = -c / b;
        return true;
    }
    float halfB = 0.5f * b;
    return closestApproachRoots(a, halfB, c, halfB * halfB - a * c, t0, t1);
}

/* Keeps a candidate hit when it is the nearest so far in (0, best). */
static inline void considerHit(float t, int part, float3 normal, float* best, int* bestPart, float3* bestNormal) {
    if (t > 0.0f && t < *best) {
        *best = t;
        *bestPart = part;
        *bestNormal = normal;
    }
}

/* Slabs, as in the reference (host/reference/shapes.cpp): inside the cube the ray runs from the
 * largest entering to the smallest leaving plane distance. Faces are numbered as parts:
 * axis·2 for the +0.5 plane, axis·2 + 1 for the −0.5 plane. */
static inline void intersectCube(float3 o, float3 d, float* best, int* part, float3* normal) {
    float tEnter = -RAY_INFINITY, tLeave = RAY_INFINITY;
    int enterFace = 0, leaveFace = 0;
    for (int axis = 0; axis < 3; ++axis) {
        float oa = axis == 0 ? o.x : (axis == 1 ? o.y : o.z);
        float da = axis == 0 ? d.x : (axis == 1 ? d.y : d.z);
        if (da == 0.0f) {
            if (oa < -0.5f || oa > 0.5f) return; /* parallel to the slab and outside it */
            continue;
        }
        float inverse = 1.0f / da;
        float tLow = (-0.5f - oa) * inverse, tHigh = (0.5f - oa) * inverse;
        int lowFace = axis * 2 + 1, highFace = axis * 2;
        if (tLow > tHigh) {
            float t = tLow;
            tLow = tHigh;
            tHigh = t;
            lowFace = axis * 2;
            highFace = axis * 2 + 1;
        }
        if (tLow > tEnter) {
            tEnter = tLow;
            enterFace = lowFace;
        }
        if (tHigh < tLeave) {
            tLeave = tHigh;
            leaveFace = highFace;
        }
    }
    if (tEnter > tLeave) return;
    /* From outside the nearest hit is where the ray enters; from inside, where it leaves. */
    bool fromOutside = tEnter > 0.0f;
    float t = fromOutside ? tEnter : tLeave;
    int face = fromOutside ? enterFace : leaveFace;
    if (!(t > 0.0f && t < *best)) return;
    float3 n = (float3)(0.0f);
    float sign = (face & 1) ? -1.0f : 1.0f;
    if (face < 2) n.x = sign;
    else if (face < 4) n.y = sign;
    else n.z = sign;
    considerHit(t, face, n, best, part, normal);
}

static inline void intersectSphere(float3 o, float3 d, float* best, int* part, float3* normal) {
    float a = dot(d, d), halfB = dot(o, d);
    float3 f = o - (halfB / a) * d; /* the ray's closest approach to the centre */
    float t0, t1;
    if (!closestApproachRoots(a, halfB, dot(o, o) - 0.25f, a * (0.25f - dot(f, f)), &t0, &t1)) return;
    float t = t0 > 0.0f ? t0 : t1;
    considerHit(t, PART_SIDE, o + t * d, best, part, normal);
}

/* A cap of radius 0.5 in the plane y = capY. */
static inline void intersectCap(float3 o, float3 d, float capY, int capPart, float* best, int* part, float3* normal) {
    if (d.y == 0.0f) return;
    float t = (capY - o.y) / d.y;
    float3 p = o + t * d;
    if (p.x * p.x + p.z * p.z <= 0.25f)
        considerHit(t, capPart, (float3)(0.0f, capY > 0.0f ? 1.0f : -1.0f, 0.0f), best, part, normal);
}

/* A root of the side surface counts when it lies between the caps. */
static inline void considerSideRoot(float3 o, float3 d, float t, int cone, float* best, int* part, float3* normal) {
    float3 p = o + t * d;
    if (p.y < -0.5f || p.y > 0.5f) return;
    float3 n = cone ? (float3)(p.x, 0.25f * (0.5f - p.y), p.z) : (float3)(p.x, 0.0f, p.z);
    considerHit(t, PART_SIDE, n, best, part, normal);
}

static inline void intersectCylinder(float3 o, float3 d, float* best, int* part, float3* normal) {
    float t0, t1;
    float a = d.x * d.x + d.z * d.z; /* 0 for a ray along the axis: the side is missed */
    float halfB = o.x * d.x + o.z * d.z;
    float fx = o.x - (halfB / a) * d.x, fz = o.z - (halfB / a) * d.z; /* closest approach to the axis */
    if (a > 0.0f && closestApproachRoots(a, halfB, o.x * o.x + o.z * o.z - 0.25f, a * (0.25f - (fx * fx + fz * fz)),
                                         &t0, &t1)) {
        considerSideRoot(o, d, t0, 0, best, part, normal);
        considerSideRoot(o, d, t1, 0, best, part, normal);
    }
    intersectCap(o, d, 0.5f, PART_TOP, best, part, normal);
    intersectCap(o, d, -0.5f, PART_BOTTOM, best, part, normal);
}

/* Side: x² + z² = ((0.5 − y) / 2)², the radius shrinking from 0.5 at the base to 0 at the
 * apex (0, 0.5, 0). */
static inline void intersectCone(float3 o, float3 d, float* best, int* part, float3* normal) {
    float k = 0.5f - o.y; /* (0.5 − y) at the origin; along the ray it is k − t·d.y */
    float a = d.x * d.x + d.z * d.z - 0.25f * d.y * d.y;
    float b = 2.0f * (o.x * d.x + o.z * d.z) + 0.5f * k * d.y;
    float c = o.x * o.x + o.z * o.z - 0.25f * k * k;
    float t0, t1;
    if (solveQuadratic(a, b, c, &t0, &t1)) {
        considerSideRoot(o, d, t0, 1, best, part, normal);
        considerSideRoot(o, d, t1, 1, best, part, normal);
    }
    intersectCap(o, d, -0.5f, PART_BOTTOM, best, part, normal);
}

/* One entry of the traversal stack (BvhStack, below). */
typedef struct {
    int node;
    float entry;
} BvhStackEntry;

/* The torus and meshes: cl/torus_mesh.cl. A mesh's walk keeps its stack in the scene
 * walk's unused entries, the `spareCount` from `spare` on (BvhStack). */
RAY_INLINED_ON_GPU void intersectTorus(float3 o, float3 d, float* best, int* part, float3* normal);
RAY_INLINED_ON_GPU
void intersectMesh(__global const RayWideBvhNode* nodes, __global const RayTriangle* triangles, int root, float3 o,
                   float3 d, BvhStackEntry* spare, int spareCount, float* best, int* part, float3* normal,
                   float2* barycentric);

/* Constructive solid geometry: cl/csg.cl. prims is the primitive buffer (the program's
 * records are indexed in it), csg the object's own record. */
RAY_INLINED_ON_GPU
void intersectCsg(__global const RayPrimitive* prims, __global const RayPrimitive* csg, float3 origin, float3 direction,
                  Hit* hit);

/* Intersects one primitive, updating hit when it is nearer than hit->t; a mesh's walk may
 * use the traversal stack's `spareCount` entries from `spare` on (BvhStack).
 * courseMeshes (--course-meshes): a mesh's hit is keyed by t_obj = t·|M⁻¹d|/|d| (the
 * course's distance along the normalized object-space direction), which replaces hit->t
 * (so the hit point is origin + t_obj·d); the world t below which that key beats hit->t,
 * hit->t/scale, bounds the mesh's own search. objectPoint stays the true one.
 * Motion blur: at time t the instance is translated by t·motion (motions[index], world
 * space), which is the same as moving the ray's origin back by it. The host sets every
 * time to 0 when nothing moves, and then the motion buffer (a placeholder) is never read. */
static RAY_CALL_ON_CPU void intersectPrimitive(__global const RayWideBvhNode* nodes, __global const RayTriangle* triangles,
                               __global const float4* motions, __global const RayPrimitive* prim, int index, Ray ray,
                               bool courseMeshes, BvhStackEntry* spare, int spareCount, Hit* hit) {
    float3 origin = ray.origin;
    if (ray.time != 0.0f) origin -= ray.time * motions[index].xyz;
    if (prim->info.x == RAY_PRIM_CSG) { /* its operands have transforms of their own */
        intersectCsg(prim - index, prim, origin, ray.direction, hit);
        return;
    }
    float3 o = transformPoint(prim->worldToObject, origin);
    float3 d = transformVector(prim->worldToObject, ray.direction);
    const bool keyed = courseMeshes && prim->info.x == RAY_PRIM_MESH;
    const float scale = keyed ? length(d) / length(ray.direction) : 1.0f;
    /* A primitive listed after the one hit so far also takes a hit at exactly hit->t. */
    const bool winsTies = hit->primitive >= 0 && prim->info.z > hit->order;
    const float limit = keyed ? hit->t / scale : (winsTies ? nextafter(hit->t, RAY_INFINITY) : hit->t);
    float best = limit;
    int part = 0;
    float3 normal = (float3)(0.0f);
    float2 barycentric = (float2)(0.0f);
    switch (prim->info.x) {
        case RAY_PRIM_CUBE: intersectCube(o, d, &best, &part, &normal); break;
        case RAY_PRIM_SPHERE: intersectSphere(o, d, &best, &part, &normal); break;
        case RAY_PRIM_CYLINDER: intersectCylinder(o, d, &best, &part, &normal); break;
        case RAY_PRIM_CONE: intersectCone(o, d, &best, &part, &normal); break;
        case RAY_PRIM_TORUS: intersectTorus(o, d, &best, &part, &normal); break;
        case RAY_PRIM_MESH:
            intersectMesh(nodes, triangles, prim->info.w, o, d, spare, spareCount, &best, &part, &normal,
                          &barycentric);
            break;
        default: break;
    }
    const float key = keyed ? best * scale : best;
    if (keyed ? (best < limit && key < hit->t) : best < limit) {
        hit->t = key;
        hit->primitive = index;
        hit->order = prim->info.z;
        hit->part = part;
        hit->objectPoint = o + best * d;
        hit->objectNormal = normal;
        hit->barycentric = barycentric;
    }
}

/* Minimum and maximum of operands that are never NaN. OpenCL's fmin and fmax must return
 * the operand that is not NaN, which costs a compare-unordered and a blend per call on
 * CPUs; a select compiles to one vminps/vmaxps (the traversal ran ~25% faster on PoCL).
 * The slab tests below never see a NaN (safeInverse), so they use these (defined with
 * each shape of the test below). */

/* Slab distances to the four children of a wide node (cl/shared_types.h): the distance at
 * which the ray enters each child's box within (0, tMax), +infinity for a child it misses
 * and for an absent one.
 *
 * Two shapes of the same arithmetic, operation for operation (so the same bits): on a CPU
 * the four children at once in float4s, which its CPU code runs as SIMD; on a GPU one child
 * at a time in floats. On a GPU each work-item's float4 is four scalar registers, and the
 * ray's coordinates spread over float4s (origin.x - node->minX and the like) became six
 * four-register splats that LLVM hoists out of the walk's loop: on gfx906 at 64 VGPRs they
 * held 24 registers for the whole walk, and renderTile spilled 800 B more scratch. On PoCL
 * the one-child shape costs 5% more instructions (chess). tests/rusticl.sh renders the
 * bundled scenes with the scalar shape and compares them with PoCL's. */
#ifdef RAY_DEVICE_CPU
/* The slab test of a wide node's children at once, lane c child c, in the vector type
 * FloatN of as many lanes as the node has children: the four-wide tree's, and the
 * sixteen-wide one CPU devices walk a ray at a time (cpuChildEntryDistances), are this one
 * definition. */
#define RAY_DEFINE_CHILD_ENTRY_DISTANCES(name, Node, FloatN)                                                      \
    static inline FloatN minNumber_##name(FloatN a, FloatN b) { return select(b, a, a < b); }                   \
    static inline FloatN maxNumber_##name(FloatN a, FloatN b) { return select(b, a, a > b); }                   \
    static inline FloatN name(__global const Node* node, float3 origin, float3 inverseDirection, float tMax) {   \
        FloatN tx0 = (node->minX - origin.x) * inverseDirection.x, tx1 = (node->maxX - origin.x) * inverseDirection.x; \
        FloatN ty0 = (node->minY - origin.y) * inverseDirection.y, ty1 = (node->maxY - origin.y) * inverseDirection.y; \
        FloatN tz0 = (node->minZ - origin.z) * inverseDirection.z, tz1 = (node->maxZ - origin.z) * inverseDirection.z; \
        FloatN tNear = maxNumber_##name(maxNumber_##name(minNumber_##name(tx0, tx1), minNumber_##name(ty0, ty1)),    \
                                        maxNumber_##name(minNumber_##name(tz0, tz1), (FloatN)(0.0f)));            \
        FloatN tFar = minNumber_##name(minNumber_##name(maxNumber_##name(tx0, tx1), maxNumber_##name(ty0, ty1)),     \
                                       minNumber_##name(maxNumber_##name(tz0, tz1), (FloatN)(tMax)));             \
        return select((FloatN)(RAY_INFINITY), tNear, (tNear <= tFar) & (node->index >= 0));                       \
    }
RAY_DEFINE_CHILD_ENTRY_DISTANCES(childEntryDistances, RayWideBvhNode, float4)
#else
static inline float minNumber(float a, float b) { return a < b ? a : b; }
static inline float maxNumber(float a, float b) { return a > b ? a : b; }

/* The entry distance into one box, [minX, maxX] × [minY, maxY] × [minZ, maxZ]. */
static inline float boxEntryDistance(float minX, float maxX, float minY, float maxY, float minZ, float maxZ,
                                     float3 origin, float3 inverseDirection, float tMax) {
    float tx0 = (minX - origin.x) * inverseDirection.x, tx1 = (maxX - origin.x) * inverseDirection.x;
    float ty0 = (minY - origin.y) * inverseDirection.y, ty1 = (maxY - origin.y) * inverseDirection.y;
    float tz0 = (minZ - origin.z) * inverseDirection.z, tz1 = (maxZ - origin.z) * inverseDirection.z;
    float tNear = maxNumber(maxNumber(minNumber(tx0, tx1), minNumber(ty0, ty1)), maxNumber(minNumber(tz0, tz1), 0.0f));
    float tFar = minNumber(minNumber(maxNumber(tx0, tx1), maxNumber(ty0, ty1)), minNumber(maxNumber(tz0, tz1), tMax));
    return tNear <= tFar ? tNear : RAY_INFINITY;
}

/* Child `lane` (s0..s3) of the node: its box's entry distance, +infinity when absent. */
#define RAY_CHILD_ENTRY(lane)                                                                                    \
    (node->index.lane >= 0 ? boxEntryDistance(node->minX.lane, node->maxX.lane, node->minY.lane, node->maxY.lane, \
                                              node->minZ.lane, node->maxZ.lane, origin, inverseDirection, tMax)   \
                           : RAY_INFINITY)
static inline float4 childEntryDistances(__global const RayWideBvhNode* node, float3 origin, float3 inverseDirection,
                                         float tMax) {
    return (float4)(RAY_CHILD_ENTRY(s0), RAY_CHILD_ENTRY(s1), RAY_CHILD_ENTRY(s2), RAY_CHILD_ENTRY(s3));
}
#undef RAY_CHILD_ENTRY
#endif

/* A wide node's four children as a walk reads them: the distance at which the ray enters
 * each (childEntryDistances: +infinity when missed or absent), its index and its count. */
typedef struct {
    float entry[4];
    int index[4];
    int count[4];
} NodeChildren;

static inline NodeChildren testChildren(__global const RayWideBvhNode* node, float3 origin, float3 inverseDirection,
                                 float tMax) {
    float4 entry = childEntryDistances(node, origin, inverseDirection, tMax);
    int4 index = node->index, count = node->count;
    NodeChildren c = {{entry.s0, entry.s1, entry.s2, entry.s3},
                      {index.s0, index.s1, index.s2, index.s3},
                      {count.s0, count.s1, count.s2, count.s3}};
    return c;
}

/* Whether a child whose entry distance is `entry` (childEntryDistances) is to be visited
 * when the nearest hit so far is at `limit`: one entered exactly there may hold a tie (see
 * Hit.order); +infinity is a miss even when nothing has been hit yet. */
static inline bool enteredBy(float entry, float limit) { return entry <= limit && entry < RAY_INFINITY; }

/* 1/d with exact zeros replaced by a tiny signed value, so that no 0·∞ NaN reaches the
 * slab test (an empty child's ±1e30 bounds then give huge but ordered distances). */
static inline float3 safeInverse(float3 d) {
    const float tiny = 1e-20f;
    return (float3)(1.0f / (fabs(d.x) > tiny ? d.x : copysign(tiny, d.x)),
                    1.0f / (fabs(d.y) > tiny ? d.y : copysign(tiny, d.y)),
                    1.0f / (fabs(d.z) > tiny ? d.z : copysign(tiny, d.z)));
}

/* The nodes still to visit, each with the distance at which the ray enters it, so that a
 * node is skipped when a hit nearer than that has been found since it was pushed.
 *
 * A short stack: a wide node pushes up to 3 of its children, so a walk may need
 * 3 · kBvhMaxDepth (host/accel/bvh.h) entries (1.5 KB) where a GPU gives a work-item a few hundred bytes of
 * fast memory. One stack serves the scene's walk and the mesh walks it makes (as GPU
 * tracers share one between the top and bottom levels): a mesh's walk, which runs while
 * the scene's is at a leaf, pushes above the scene's entries and is back at its own base
 * when it returns (intersectMesh). RAY_BVH_SHORT_STACK entries hold every walk of the
 * bundled and course scenes, the deepest scene walk and mesh walk on top of each other
 * included; a walk that would push more stops (overflowed) and then tests every primitive
 * (or triangle) under its own root instead (everyPrimitiveUnder), leaving the entries
 * below its base alone, which finds the same hit: hits are ranked by distance and then by
 * order (Hit.order), whatever the order in which they are found. Exact, and slow only for
 * the rare ray that overflows. The host may set it with -DRAY_BVH_SHORT_STACK (tests force
 * overflows with a tiny one). */
#ifndef RAY_BVH_SHORT_STACK
#define RAY_BVH_SHORT_STACK 24
#endif
/* One walk's view of the stack: its `capacity` entries from `entries` on (the whole stack
 * for the scene's walk, the scene's spare entries for a mesh's). */
typedef struct {
    BvhStackEntry* entries;
    int capacity;
    int top;
    bool overflowed;
} BvhStack;

static inline BvhStack emptyBvhStack(BvhStackEntry* entries, int capacity) {
    BvhStack stack = {entries, capacity, 0, false};
    return stack;
}

/* The primitives (or a mesh's triangles) under wide node `root`, as [x, y): leaves hold
 * them in the tree's order (cl/shared_types.h) and a node's children are in that order
 * too, absent ones last, so the range runs from the first leaf of the leftmost path to the
 * end of the last leaf of the rightmost. */
static inline int2 leafRange(__global const RayWideBvhNode* nodes, int root) {
    int node = root;
    while (nodes[node].index.x >= 0 && nodes[node].count.x == 0) node = nodes[node].index.x;
    if (nodes[node].index.x < 0) return (int2)(0, 0); /* an empty tree */
    int first = nodes[node].index.x;
    node = root;
    while (true) {
        int4 index = nodes[node].index, count = nodes[node].count;
        int lane = index.w >= 0 ? 3 : index.z >= 0 ? 2 : index.y >= 0 ? 1 : 0;
        int laneIndex = lane == 3 ? index.w : lane == 2 ? index.z : lane == 1 ? index.y : index.x;
        int laneCount = lane == 3 ? count.w : lane == 2 ? count.z : lane == 1 ? count.y : count.x;
        if (laneCount > 0) return (int2)(first, laneIndex + laneCount);
        node = laneIndex;
    }
}

/* A walk's fallback step: one leaf, entered at 0, holding every primitive under `root`
 * (BvhStack). Put in place of a node's children, it sends them through the walk's own leaf
 * loop, so that a GPU compiler, which inlines every call site, makes no second copy of it. */
static inline NodeChildren everyPrimitiveUnder(__global const RayWideBvhNode* nodes, int root) {
    int2 range = leafRange(nodes, root);
    NodeChildren all = {{range.y > range.x ? 0.0f : RAY_INFINITY, RAY_INFINITY, RAY_INFINITY, RAY_INFINITY},
                        {range.x, -1, -1, -1},
                        {range.y - range.x, 0, 0, 0}};
    return all;
}

/* The walk's step after nextNode's answer `next`: the node to visit, or, when the walk is
 * over (-1) because its stack overflowed, RAY_WALK_EVERY_PRIMITIVE: one more step, over
 * every primitive under the walk's root (everyPrimitiveUnder), with the stack emptied so
 * that nextNode answers -1 after it. The overflow is looked at here, where a walk ends,
 * and not at every node (a fallback flag tested at each node cost PoCL about 1% of the
 * walk's instructions). Written as one NodeChildren chosen at the top of the loop, which
 * gfx906 builds in 144 B less scratch than a loop whose children come from a helper that
 * writes them through a pointer (faster on PoCL by 4%). */
#define RAY_WALK_EVERY_PRIMITIVE (-2)

/* The sixteen-wide walk of CPU devices (traceBvh) holds both kinds of node in one stack: its
 * own by their index (>= 0), and the four-wide nodes it goes on into (a child of count -1,
 * RayCpuBvhNode) as fourWideRef(index) (<= -3, below the walk's other values). */
static inline int fourWideRef(int node) { return -3 - node; }
static inline int afterOverflow(int next, BvhStack* stack) {
    if (next >= 0 || !stack->overflowed) return next;
    stack->overflowed = false;
    stack->top = 0;
    return RAY_WALK_EVERY_PRIMITIVE;
}

/* The inner children of one node that the ray enters; with `ordered`, farthest first. */
typedef struct {
    int node[4];
    float entry[4];
    int count;
} InnerChildren;

static inline void addInnerChild(InnerChildren* inner, int node, float entry, bool ordered) {
    int i = inner->count++;
    while (ordered && i > 0 && inner->entry[i - 1] < entry) {
        inner->node[i] = inner->node[i - 1];
        inner->entry[i] = inner->entry[i - 1];
        --i;
    }
    inner->node[i] = node;
    inner->entry[i] = entry;
}

/* The step after a node's children have been tested, shared by the scene's walk and each
 * mesh's (cl/torus_mesh.cl): descend into the last (nearest) inner child still entered
 * by `limit` and push the others, or resume from the stack, skipping the nodes entered
 * beyond `limit` (a node entered exactly there may hold a tie: see Hit.order). Returns the
 * next node, or -1 when the walk is over. */
static inline int nextNode(const InnerChildren* inner, BvhStack* stack, float limit) {
    int next = -1;
    for (int i = 0; i < inner->count; ++i) {
        if (!enteredBy(inner->entry[i], limit)) continue;
        if (next >= 0) {
            if (stack->top == stack->capacity) {
                stack->overflowed = true; /* the caller falls back to every primitive */
                return -1;
            }
            BvhStackEntry pushed = {inner->node[next], inner->entry[next]};
            stack->entries[stack->top++] = pushed;
        }
        next = i;
    }
    if (next >= 0) return inner->node[next];
    while (stack->top > 0) {
        --stack->top;
        if (enteredBy(stack->entries[stack->top].entry, limit)) return stack->entries[stack->top].node;
    }
    return -1;
}

/* The distance beyond which traceBvh skips a box: the nearest hit so far, or none under
 * courseMeshes (see traceBvh). */
static inline float pruneDistance(const Hit* hit, bool courseMeshes) { return courseMeshes ? RAY_INFINITY : hit->t; }

/* Whether a walk with anyHit (traceBvh) is over: it has found a hit. The walk then ends
 * where every walk ends, at the bottom of its loop, and not with a return from inside it:
 * after gfx906's control-flow structurizer, that return left a path around the end of the
 * stack's lifetime, so that the primary trace and the shadow trace (two inlined walks)
 * could not share their stacks' scratch. */
static inline bool anyHitFound(bool anyHit, const Hit* hit) { return anyHit && hit->primitive >= 0; }

/* A walk's start: no hit below tMax yet. */
static inline void startTrace(Hit* hit, float tMax) {
    hit->t = tMax;
    hit->primitive = -1;
    hit->order = 0; /* read (as a select) before any hit is recorded */
}

/* Intersects the primitives [first, first + count) (a leaf) for the ray, a mesh's walk among
 * them using the stack's free entries. */
static inline void intersectLeaf(__global const RayWideBvhNode* nodes, __global const RayPrimitive* prims,
                                 __global const RayTriangle* triangles, __global const float4* motions, Ray ray,
                                 bool courseMeshes, const BvhStack* stack, int first, int count, Hit* hit) {
    for (int i = first; i < first + count; ++i)
        intersectPrimitive(nodes, triangles, motions, &prims[i], i, ray, courseMeshes, stack->entries + stack->top,
                           stack->capacity - stack->top, hit);
}

/* One step of the four-wide walk (traceBvh): node `node`'s children tested, the leaves among
 * them intersected, the nearest inner child entered next and the others pushed, or the walk
 * resumed from the stack; at RAY_WALK_EVERY_PRIMITIVE, every primitive under the root at
 * once (afterOverflow). Returns the next node, -1 when the walk is over. With fourWideRefs,
 * the inner children are handed on as references into the four-wide tree from the
 * sixteen-wide walk of CPU devices (fourWideRef). */
static inline RAY_INLINED_ON_GPU
int fourWideStep(__global const RayWideBvhNode* nodes, __global const RayPrimitive* prims,
                 __global const RayTriangle* triangles, __global const float4* motions, Ray ray,
                 float3 inverseDirection, bool anyHit, bool courseMeshes, bool fourWideRefs, BvhStack* stack,
                 int node, Hit* hit) {
    /* The prune distance, read once for the node's boxes and children and again only after a
     * leaf's primitives, where it changes: read at each use, PoCL reloaded hit->t through the
     * pointer that intersectPrimitive (a call there) writes, 3 instructions each time (chess
     * 130.5 -> 122.6 M). */
    float limit = pruneDistance(hit, courseMeshes);
    NodeChildren children = node == RAY_WALK_EVERY_PRIMITIVE
                                ? everyPrimitiveUnder(nodes, 0)
                                : testChildren(&nodes[node], ray.origin, inverseDirection, limit);
    InnerChildren inner;
    inner.count = 0;
    for (int c = 0; c < 4; ++c) {
        if (!enteredBy(children.entry[c], limit)) continue;
        const int first = children.index[c], count = children.count[c];
        if (count > 0) {
            intersectLeaf(nodes, prims, triangles, motions, ray, courseMeshes, stack, first, count, hit);
            if (anyHitFound(anyHit, hit)) break;
            limit = pruneDistance(hit, courseMeshes);
        } else {
            addInnerChild(&inner, fourWideRefs ? fourWideRef(first) : first, children.entry[c], !anyHit);
        }
    }
    return anyHitFound(anyHit, hit) ? -1 : afterOverflow(nextNode(&inner, stack, limit), stack);
}

#ifdef RAY_DEVICE_CPU
/* CPU devices walk the sixteen-wide tree (RayCpuBvhNode, cl/shared_types.h): the children
 * of a node are tested in one float16 slab test, and the children entered become bit masks,
 * so that a step's branches are one per leaf entered and one on how many inner children
 * are, rather than two a child. Below the sixteen-wide nodes the walk goes on in the
 * four-wide tree (fourWideStep, children of count -1), one stack holding nodes of both.
 * The stack holds the up to fifteen children a step pushes: three times
 * RAY_BVH_SHORT_STACK (a test's tiny short stack still makes it overflow). */
#define RAY_CPU_BVH_STACK (3 * RAY_BVH_SHORT_STACK)

static inline bool isFourWideRef(int next) { return next <= -3; } /* fourWideRef */

/* childEntryDistances for the sixteen children: the same arithmetic, a lane a child. */
RAY_DEFINE_CHILD_ENTRY_DISTANCES(cpuChildEntryDistances, RayCpuBvhNode, float16)

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
    if (inners != 0) {
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
        for (int i = 0; i + 1 < n; ++i) {
            if (stack->top == stack->capacity) {
                stack->overflowed = true; /* the caller falls back to every primitive */
                return -1;
            }
            BvhStackEntry pushed = {child[i], key[i]};
            stack->entries[stack->top++] = pushed;
        }
        return child[n - 1];
    }
    while (stack->top > 0) {
        --stack->top;
        if (enteredBy(stack->entries[stack->top].entry, limit)) return stack->entries[stack->top].node;
    }
    return -1;
}
#endif

/* Closest hit below tMax (hit->primitive = -1 when none), or with anyHit, the first hit
 * found (shadow rays, which visit children in node order: any occluder will do).
 * Returns whether anything was hit. Leaves are intersected as their parent is visited.
 * courseMeshes: meshes keyed by t_obj (intersectPrimitive). A mesh's key can be smaller
 * than its world t, so boxes are then not pruned by distance (every box the ray enters is
 * visited; hits are still compared by key): exact, slower. GPUs walk the four-wide tree
 * (nodes), CPU devices the sixteen-wide one (cpuNodes); both find the same hit, hits being
 * ranked by distance and then by order (Hit.order) whatever the order of the walk. */
RAY_INLINED_ON_GPU bool traceBvh(__global const RayWideBvhNode* nodes, __global const RayCpuBvhNode* cpuNodes,
                                   __global const RayPrimitive* prims, __global const RayTriangle* triangles,
                                   __global const float4* motions, Ray ray, float tMax, bool anyHit,
                                   bool courseMeshes, Hit* hit) {
    startTrace(hit, tMax);
    float3 inverseDirection = safeInverse(ray.direction);
#ifdef RAY_DEVICE_CPU
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
        int16 entered = (entry <= (float16)(limit)) & (entry < (float16)(RAY_INFINITY));
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
#else
    (void)cpuNodes; /* CPU devices' tree: the walk above */
    BvhStackEntry entries[RAY_BVH_SHORT_STACK];
    BvhStack stack = emptyBvhStack(entries, RAY_BVH_SHORT_STACK);
    int next = 0;
    do {
        next = fourWideStep(nodes, prims, triangles, motions, ray, inverseDirection, anyHit, courseMeshes, false,
                            &stack, next, hit);
    } while (next != -1);
#endif
    return hit->primitive >= 0;
}
