/* A mesh's triangles (SPEC §2), in object space: the triangle test and the rule that ranks
 * its hits, written once over lanes (cl/lanes/one_ray.h) like the convex shapes
 * (cl/geometry/shapes.cl), and compiled for one ray (the walk of a mesh's own tree,
 * intersectMesh, cl/geometry/torus_mesh.cl) and, in a packet build, for a packet (the packet
 * walk of a mesh's tree, cl/device/cpu/packet_trace.cl), whose every lane then gets one
 * ray's answer to the bit. */

#ifdef RAY_LANE_VOCABULARY

/* A search through a mesh's triangles: the nearest t so far, the triangle hit there (-1:
 * none yet) and the weights of its corners 1 and 2 there. The face normal is left to the
 * end, from the triangle found (cross(e1, e2)), rather than kept for every hit on the way. A
 * lane whose search is not to change starts with a negative best. */
typedef struct {
    LaneFloat best;
    LaneInt part;
    LaneFloat b1, b2;
} RAY_LANE_FN(TriangleHit);

/* Möller–Trumbore against one triangle (p0, e1 = p1 − p0, e2 = p2 − p0), triangle `index`
 * of the mesh's buffer. A hit counts within (0, best); at best itself it takes the place of
 * a triangle of a higher index. Two triangles meet a ray at exactly the same t where they
 * share the point hit (an edge, a vertex, a face listed twice), and the lower index then
 * wins whatever the order in which a walk meets them: a ray's walk, which orders a node's
 * children by its own entry distances, and a packet's, which orders them by its nearest
 * ray's, find the same triangle. Within a leaf, visited in index order, the rule is the
 * first found, as before it was written. */
static inline void RAY_LANE_FN(intersectTriangle)(__global const RayTriangle* triangle, int index, LaneVec3 o,
                                                  LaneVec3 d, RAY_LANE_FN(TriangleHit) * h) {
    const float3 p0 = triangle->p0.xyz, e1 = triangle->e1.xyz, e2 = triangle->e2.xyz;
    LaneVec3 pv = laneCrossUniform(d, e2);
    LaneFloat det = laneRowDot(triangle->e1, pv);
    LaneInt hit = det != (LaneFloat)(0.0f);
    if (!laneAny(hit)) return;
    LaneFloat inverseDet = 1.0f / det;
    LaneVec3 tv = laneVec3(o.x - p0.x, o.y - p0.y, o.z - p0.z);
    LaneFloat b1 = laneDot(tv, pv) * inverseDet;
    hit &= laneNot((b1 < (LaneFloat)(0.0f)) | (b1 > (LaneFloat)(1.0f)));
    if (!laneAny(hit)) return;
    LaneVec3 qv = laneCrossUniform(tv, e1);
    LaneFloat b2 = laneDot(d, qv) * inverseDet;
    hit &= laneNot((b2 < (LaneFloat)(0.0f)) | (b1 + b2 > (LaneFloat)(1.0f)));
    if (!laneAny(hit)) return;
    LaneFloat t = laneRowDot(triangle->e2, qv) * inverseDet;
    LaneInt take = hit & (t > (LaneFloat)(0.0f)) &
                   ((t < h->best) | ((t == h->best) & ((LaneInt)(index) < h->part)));
    if (!laneAny(take)) return;
    h->best = laneSelect(h->best, t, take);
    h->part = laneSelect(h->part, (LaneInt)(index), take);
    h->b1 = laneSelect(h->b1, b1, take);
    h->b2 = laneSelect(h->b2, b2, take);
}

/* The triangles [first, first + count) of a mesh's leaf. */
static inline void RAY_LANE_FN(intersectTriangles)(__global const RayTriangle* triangles, int first, int count,
                                                   LaneVec3 o, LaneVec3 d, RAY_LANE_FN(TriangleHit) * h) {
    for (int i = first; i < first + count; ++i) RAY_LANE_FN(intersectTriangle)(&triangles[i], i, o, d, h);
}

#endif /* RAY_LANE_VOCABULARY */
