/* The traversal stack: the nodes a walk has still to visit, each with the distance at which
 * the ray (each ray of a packet: a lane a ray) enters it, so that a node is skipped when a
 * nearer hit has been found since it was pushed. Written once over lanes
 * (cl/lanes/one_ray.h) and compiled for one ray (BvhStack: the scene's walks on every device
 * and the mesh walks) and, in a packet build, for a packet (BvhStackPacket: the packet walk).
 *
 * A walk's stack is short: it holds `capacity` entries, and a walk that would push more is
 * told so (pushNode returns false, and `overflowed` stays set), then finishes its search in
 * a way that needs no stack (each walk says how: afterOverflow, cl/traversal/wide_walk.cl;
 * the packet walk's rays each walk alone), which finds the same hits, since hits are ranked
 * by distance and then by order (hitLimit, cl/geometry/shapes.cl) whatever the order in
 * which they are found. */

#ifdef RAY_LANE_VOCABULARY

typedef struct {
    LaneFloat entry; /* +infinity in a lane that does not enter the node */
    int node;
} RAY_LANE_FN(BvhStackEntry);

/* One walk's view of a stack: its `capacity` entries from `entries` on. */
typedef struct {
    RAY_LANE_FN(BvhStackEntry) * entries;
    int capacity;
    int top;
    bool overflowed;
} RAY_LANE_FN(BvhStack);

static inline RAY_LANE_FN(BvhStack) RAY_LANE_FN(emptyBvhStack)(RAY_LANE_FN(BvhStackEntry) * entries, int capacity) {
    RAY_LANE_FN(BvhStack) stack = {entries, capacity, 0, false};
    return stack;
}

/* Whether a node or child whose entry distance is `entry` is to be visited, in each lane,
 * when the nearest hit so far is at `limit`: one entered exactly there may hold a tie
 * (hitLimit); +infinity is a miss even when nothing has been hit yet. */
static inline LaneInt RAY_LANE_FN(enteredBy)(LaneFloat entry, LaneFloat limit) {
    return (entry <= limit) & (entry < (LaneFloat)(RAY_INFINITY));
}

/* Pushes a node, or, on a full stack, marks it overflowed and returns false. */
static inline bool RAY_LANE_FN(pushNode)(RAY_LANE_FN(BvhStack) * stack, int node, LaneFloat entry) {
    if (stack->top == stack->capacity) {
        stack->overflowed = true;
        return false;
    }
    RAY_LANE_FN(BvhStackEntry) pushed = {entry, node};
    stack->entries[stack->top++] = pushed;
    return true;
}

/* Pops the nodes that no lane enters by `limit` any more and returns the first that some
 * lane does, or -1 when the stack runs out. */
static inline int RAY_LANE_FN(popNode)(RAY_LANE_FN(BvhStack) * stack, LaneFloat limit) {
    while (stack->top > 0) {
        --stack->top;
        if (laneAny(RAY_LANE_FN(enteredBy)(stack->entries[stack->top].entry, limit)))
            return stack->entries[stack->top].node;
    }
    return -1;
}

#endif /* RAY_LANE_VOCABULARY */
