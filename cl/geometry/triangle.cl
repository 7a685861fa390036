/* A mesh's triangles (SPEC §2), in object space: the triangle test, written once over lanes
 * (cl/lanes/one_ray.h) like the convex shapes (cl/geometry/shapes.cl), and the rule that
 * ranks its hits. The test is compiled three times: for one ray and one triangle (a GPU's
 * walk of a mesh's tree), for one ray and a record's four triangles at once (the lanes
 * triangles, cl/lanes/quad.h: a CPU's walk a ray at a time), and in a packet build for a
 * packet and one triangle (the packet walk of a mesh's tree, cl/device/cpu/packet_trace.cl),
 * every instance giving each (ray, triangle) pair the same bits. Which instance a leaf's
 * triangles go through is the device's (cl/device/ * /triangle_test.cl, and the packet walk). */

#ifdef RAY_LANE_VOCABULARY

/* Möller–Trumbore: where each lane's ray (o, d) meets its triangle (corner p0, edges e1 =
 * p1 − p0, e2 = p2 − p0), as the distance *t and the weights *b1, *b2 of corners 1 and 2
 * there. Returns the lanes that hit in front of the origin (t > 0); the others' outputs are
 * left undefined. Leaves as soon as no lane can hit. */
RAY_LANE_TEMPLATE LaneInt RAY_LANE_FN(triangleHits)(LaneVec3 o, LaneVec3 d, LaneVec3 p0, LaneVec3 e1, LaneVec3 e2,
                                                   LaneFloat* t, LaneFloat* b1, LaneFloat* b2) {
    LaneVec3 pv = laneCross(d, e2);
    LaneFloat det = laneDot(e1, pv);
    LaneInt hit = det != (LaneFloat)(0.0f);
    if (!laneAny(hit)) return hit;
    LaneFloat inverseDet = 1.0f / det;
    LaneVec3 tv = laneVec3(o.x - p0.x, o.y - p0.y, o.z - p0.z);
    *b1 = laneDot(tv, pv) * inverseDet;
    hit &= laneNot((*b1 < (LaneFloat)(0.0f)) | (*b1 > (LaneFloat)(1.0f)));
    if (!laneAny(hit)) return hit;
    LaneVec3 qv = laneCross(tv, e1);
    *b2 = laneDot(d, qv) * inverseDet;
    hit &= laneNot((*b2 < (LaneFloat)(0.0f)) | (*b1 + *b2 > (LaneFloat)(1.0f)));
    if (!laneAny(hit)) return hit;
    *t = laneDot(e2, qv) * inverseDet;
    return hit & (*t > (LaneFloat)(0.0f));
}

#ifndef RAY_LANES_ARE_TRIANGLES

/* A search through a mesh's triangles, a lane a ray: the nearest t so far, the triangle hit
 * there (its slot, RayTriangle4; -1: none yet) and the weights of its corners 1 and 2 there.
 * The face normal is left to the end, from the triangle found (triangleFaceNormal), rather
 * than kept for every hit on the way. A lane whose search is not to change starts with a
 * negative best. */
typedef struct {
    LaneFloat best;
    LaneInt part;
    LaneFloat b1, b2;
} RAY_LANE_FN(TriangleHit);

/* Whether a hit at t on triangle `index` takes the place of the search's: within (0, best),
 * and at best itself in place of a triangle of a higher index. Two triangles meet a ray at
 * exactly the same t where they share the point hit (an edge, a vertex, a face listed twice),
 * and the lower index then wins whatever the order in which a walk meets them: a ray's walk,
 * which orders a node's children by its own entry distances, and a packet's, which orders
 * them by its nearest ray's, find the same triangle. */
static inline LaneInt RAY_LANE_FN(takesTriangleHit)(const RAY_LANE_FN(TriangleHit) * h, LaneFloat t, LaneInt index) {
    return (t < h->best) | ((t == h->best) & (index < h->part));
}

/* Triangle `index` (p0, e1, e2, shared by every lane) for every lane's ray. */
RAY_LANE_TEMPLATE void RAY_LANE_FN(intersectTriangle)(float3 p0, float3 e1, float3 e2, int index, LaneVec3 o,
                                                     LaneVec3 d, RAY_LANE_FN(TriangleHit) * h) {
    LaneFloat t, b1, b2;
    LaneInt hit = RAY_LANE_FN(triangleHits)(o, d, laneVec3((LaneFloat)(p0.x), (LaneFloat)(p0.y), (LaneFloat)(p0.z)),
                                            laneVec3((LaneFloat)(e1.x), (LaneFloat)(e1.y), (LaneFloat)(e1.z)),
                                            laneVec3((LaneFloat)(e2.x), (LaneFloat)(e2.y), (LaneFloat)(e2.z)), &t, &b1,
                                            &b2);
    if (!laneAny(hit)) return;
    LaneInt take = hit & RAY_LANE_FN(takesTriangleHit)(h, t, (LaneInt)(index));
    if (!laneAny(take)) return;
    h->best = laneSelect(h->best, t, take);
    h->part = laneSelect(h->part, (LaneInt)(index), take);
    h->b1 = laneSelect(h->b1, b1, take);
    h->b2 = laneSelect(h->b2, b2, take);
}

/* The triangles in slots [first, first + count) (a mesh's leaf, or on a walk's overflow every
 * leaf under a node: cl/traversal/wide_walk.cl leafRange) for every lane's ray, one after
 * another in slot order: a GPU's ray (cl/device/gpu/triangle_test.cl) and a packet. */
RAY_LANE_TEMPLATE void RAY_LANE_FN(intersectTriangleSlots)(__global const RayTriangle4* records, int first, int count,
                                                          LaneVec3 o, LaneVec3 d, RAY_LANE_FN(TriangleHit) * h) {
    for (int slot = first; slot < first + count; ++slot) {
        float3 p0, e1, e2;
        triangleOfSlot(records, slot, &p0, &e1, &e2);
        RAY_LANE_FN(intersectTriangle)(p0, e1, e2, slot, o, d, h);
    }
}

#else /* the lanes are a record's triangles (cl/lanes/quad.h) */

/* One ray against the triangles in slots [first, first + count), a record's four at once:
 * the hits of each record ranked in slot order by the rule of one triangle at a time
 * (takesTriangleHit), so that the search ends where testing them one by one ends it. */
static inline void intersectTriangleRecordsQuad(__global const RayTriangle4* records, int first, int count, float3 o,
                                                float3 d, TriangleHit* h) {
    const QuadVec3 origin = quadVec3((float4)(o.x), (float4)(o.y), (float4)(o.z));
    const QuadVec3 direction = quadVec3((float4)(d.x), (float4)(d.y), (float4)(d.z));
    for (int record = first >> 2, end = first + count; record << 2 < end; ++record) {
        __global const RayTriangle4* r = &records[record];
        const int4 slot = (int4)(record << 2) + (int4)(0, 1, 2, 3);
        float4 t, b1, b2;
        int4 hit = triangleHitsQuad(origin, direction, quadVec3(r->p0x, r->p0y, r->p0z),
                                    quadVec3(r->e1x, r->e1y, r->e1z), quadVec3(r->e2x, r->e2y, r->e2z), &t, &b1, &b2);
        hit &= (slot >= (int4)(first)) & (slot < (int4)(end));
        if (!any(hit)) continue;
        const float tLane[4] = {t.s0, t.s1, t.s2, t.s3}, b1Lane[4] = {b1.s0, b1.s1, b1.s2, b1.s3},
                    b2Lane[4] = {b2.s0, b2.s1, b2.s2, b2.s3};
        const int hitLane[4] = {hit.s0, hit.s1, hit.s2, hit.s3};
        for (int k = 0; k < 4; ++k) {
            const int index = (record << 2) + k;
            if (!hitLane[k] || !takesTriangleHit(h, tLane[k], index)) continue;
            h->best = tLane[k];
            h->part = index;
            h->b1 = b1Lane[k];
            h->b2 = b2Lane[k];
        }
    }
}

#endif /* RAY_LANES_ARE_TRIANGLES */
#endif /* RAY_LANE_VOCABULARY */
