/* The walk of a four-wide BVH (RayWideBvhNode) a ray at a time, a step at a time: the
 * scene's walk on a GPU (cl/device/gpu/walk.cl), its walk below the sixteen-wide nodes on a
 * CPU (cl/device/cpu/walk.cl), and every mesh's walk (cl/geometry/torus_mesh.cl). How a
 * node's four boxes are tested is the device's (childEntryDistances, cl/device/ * /box_test.cl).
 *
 * The stack is short (BvhStack, cl/traversal/stack.cl): a wide node pushes up to 3 of its
 * children, so a walk may need 3 · kBvhMaxDepth (host/accel/bvh.h) entries (1.5 KB) where a
 * GPU gives a work-item a few hundred bytes of fast memory. One stack serves the scene's walk
 * and the mesh walks it makes (as GPU tracers share one between the top and bottom levels): a
 * mesh's walk, which runs while the scene's is at a leaf, pushes above the scene's entries and
 * is back at its own base when it returns (intersectMesh). RAY_BVH_SHORT_STACK entries hold
 * every walk of the bundled and course scenes, the deepest scene walk and mesh walk on top of
 * each other included; a walk that would push more stops (overflowed) and then tests every
 * primitive (or triangle) under its own root instead (everyPrimitiveUnder), leaving the
 * entries below its base alone, which finds the same hit. Exact, and slow only for the rare
 * ray that overflows. The host may set it with -DRAY_BVH_SHORT_STACK (tests force overflows
 * with a tiny one). */
#ifndef RAY_BVH_SHORT_STACK
#define RAY_BVH_SHORT_STACK 24
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

/* A walk's fallback step: one leaf, entered at 0, holding every primitive under `root`.
 * Put in place of a node's children, it sends them through the walk's own leaf loop, so
 * that a GPU compiler, which inlines every call site, makes no second copy of it. */
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
 * that nextNode answers -1 after it. The overflow is looked at here, where a walk ends, and
 * not at every node, where a flag would cost every walk a test a node. The step takes its
 * children as one NodeChildren chosen at its top (fourWideStep), rather than from a helper
 * that writes them through a pointer, which costs a GPU scratch (docs/performance.md, "The
 * kernel on GPUs"). */
#define RAY_WALK_EVERY_PRIMITIVE (-2)
static inline int afterOverflow(int next, BvhStack* stack) {
    if (next >= 0 || !stack->overflowed) return next;
    stack->overflowed = false;
    stack->top = 0;
    return RAY_WALK_EVERY_PRIMITIVE;
}

/* The sixteen-wide walk of CPU devices (cl/device/cpu/walk.cl) holds both kinds of node in
 * one stack: its own by their index (>= 0), and the four-wide nodes it goes on into (a child
 * of count -1, RayCpuBvhNode) as fourWideRef(index) (<= -3, below the walk's other values). */
static inline int fourWideRef(int node) { return -3 - node; }

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
 * mesh's: descend into the last (nearest) inner child still entered by `limit` and push the
 * others, or resume from the stack, skipping the nodes entered beyond `limit` (enteredBy).
 * Returns the next node, or -1 when the walk is over (an overflow included: afterOverflow). */
static inline int nextNode(const InnerChildren* inner, BvhStack* stack, float limit) {
    int next = -1;
    for (int i = 0; i < inner->count; ++i) {
        if (!enteredBy(inner->entry[i], limit)) continue;
        if (next >= 0 && !pushNode(stack, inner->node[next], inner->entry[next])) return -1;
        next = i;
    }
    return next >= 0 ? inner->node[next] : popNode(stack, limit);
}

/* The distance beyond which a walk skips a box: the nearest hit so far, or none under
 * courseMeshes (see traceBvh). */
static inline float pruneDistance(const Hit* hit, bool courseMeshes) { return courseMeshes ? RAY_INFINITY : hit->t; }

/* Whether a walk with anyHit (traceBvh) is over: it has found a hit. The walk then ends
 * where every walk ends, at the bottom of its loop, and not with a return from inside it:
 * after gfx906's control-flow structurizer, such a return left a path around the end of the
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
                                 __global const RayTriangle4* triangles, __global const float4* motions, Ray ray,
                                 bool courseMeshes, const BvhStack* stack, int first, int count, Hit* hit) {
    for (int i = first; i < first + count; ++i)
        intersectPrimitive(nodes, triangles, motions, &prims[i], i, ray, courseMeshes, stack->entries + stack->top,
                           stack->capacity - stack->top, hit);
}

/* One step of the four-wide walk: node `node`'s children tested, the leaves among them
 * intersected, the nearest inner child entered next and the others pushed, or the walk
 * resumed from the stack; at RAY_WALK_EVERY_PRIMITIVE, every primitive under the root at
 * once (afterOverflow). Returns the next node, -1 when the walk is over. With fourWideRefs,
 * the inner children are handed on as references into the four-wide tree from the
 * sixteen-wide walk of CPU devices (fourWideRef). */
static inline RAY_INLINED_ON_GPU
int fourWideStep(__global const RayWideBvhNode* nodes, __global const RayPrimitive* prims,
                 __global const RayTriangle4* triangles, __global const float4* motions, Ray ray,
                 float3 inverseDirection, bool anyHit, bool courseMeshes, bool fourWideRefs, BvhStack* stack,
                 int node, Hit* hit) {
    /* The prune distance, read once for the node's boxes and children and again only after a
     * leaf's primitives, where it changes: read at each use, it is reloaded through the
     * pointer that intersectPrimitive (a call on a CPU) writes. */
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
