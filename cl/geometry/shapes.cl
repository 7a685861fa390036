/* The unit primitives of SPEC §2 that have closed-form intersections (the cube, sphere,
 * cylinder and cone: the convex shapes), the transform into a primitive's object space, and
 * the rule that breaks ties between hits: written once, over lanes (cl/lanes/one_ray.h),
 * and compiled for one ray and, in a packet build, for a packet, whose every lane then gets
 * one ray's answer to the bit (tests/cpu_paths.sh compares the two paths' images). A mesh's
 * triangles are written the same way (cl/geometry/triangle.cl); the torus
 * (cl/geometry/torus_mesh.cl) and csg objects (cl/geometry/csg.cl) are intersected a ray at
 * a time, and the reference renderer (host/reference/shapes.cpp) does the same in double,
 * apart, as the oracle.
 *
 * Written as masks rather than branches, so that each lane does what one ray does; laneAny
 * skips what no lane needs. */

#ifdef RAY_LANE_VOCABULARY

/* A point and a direction carried into object space by a primitive's world-to-object
 * rows (translation in .w). */
static inline LaneVec3 RAY_LANE_FN(transformPoint)(__global const float4* m, LaneVec3 p) {
    return laneVec3(laneRowDot(m[0], p) + m[0].w, laneRowDot(m[1], p) + m[1].w, laneRowDot(m[2], p) + m[2].w);
}

static inline LaneVec3 RAY_LANE_FN(transformVector)(__global const float4* m, LaneVec3 v) {
    return laneVec3(laneRowDot(m[0], v), laneRowDot(m[1], v), laneRowDot(m[2], v));
}

/* The distance below which a primitive of order `candidateOrder` (RayPrimitive.order) takes
 * the hit from the nearest so far (at t, primitive `primitive` of order `order`; primitive
 * -1: none yet): t, or just past it where the candidate is listed later in the scene.
 * Exact ties (coplanar faces) so go to the primitive listed last, as in the reference
 * renderer (host/reference/reference_bvh.cpp), whatever the order a walk finds them in. */
static inline LaneFloat RAY_LANE_FN(hitLimit)(LaneFloat t, LaneInt primitive, LaneInt order, int candidateOrder) {
    LaneInt winsTies = (primitive >= (LaneInt)(0)) & ((LaneInt)(candidateOrder) > order);
    return laneSelect(t, nextafter(t, (LaneFloat)(RAY_INFINITY)), winsTies);
}

/* A shape's search in object space: the nearest t so far, and that hit's part and outward
 * object normal (unnormalized). A lane whose search is not to change starts with a negative
 * best: considerHit takes only 0 < t < best. */
typedef struct {
    LaneFloat best;
    LaneInt part;
    LaneVec3 normal;
} RAY_LANE_FN(ShapeHit);

/* Keeps a candidate hit, in the lanes of `candidate`, where it is the nearest so far in
 * (0, best). */
static inline void RAY_LANE_FN(considerHit)(LaneInt candidate, LaneFloat t, LaneInt part, LaneVec3 normal,
                                            RAY_LANE_FN(ShapeHit) * h) {
    LaneInt take = candidate & (t > (LaneFloat)(0.0f)) & (t < h->best);
    if (laneEarlyOut(take)) return;
    h->best = laneSelect(h->best, t, take);
    h->part = laneSelect(h->part, part, take);
    h->normal = laneSelectVec3(h->normal, normal, take);
}

/* The roots of a t² + 2·halfB·t + c = 0, ascending, given its quarter discriminant
 * halfB² − a·c, in the lanes that have them (the mask returned). The sphere and the
 * cylinder compute that discriminant from the ray's closest approach to the centre or axis,
 * a·(r² − |f|²): the schoolbook b² − 4ac cancels catastrophically in float when the shape is
 * small against its distance (tiny spheres whose object-space origins are thousands of
 * radii away), that form does not. The roots come from q and c/q, without a second
 * cancellation (host/reference/shapes.cpp does the same). Where no lane has roots, the roots
 * are set to 0, so that no caller's select reads a value never set. */
static inline LaneInt RAY_LANE_FN(closestApproachRoots)(LaneFloat a, LaneFloat halfB, LaneFloat c,
                                                        LaneFloat discriminant, LaneFloat* t0, LaneFloat* t1) {
    LaneInt found = (discriminant >= (LaneFloat)(0.0f)) & (a != (LaneFloat)(0.0f));
    if (!laneAny(found)) {
        *t0 = *t1 = (LaneFloat)(0.0f);
        return found;
    }
    LaneFloat q = -(halfB + copysign(sqrt(discriminant), halfB));
    LaneFloat r0 = q / a;
    LaneFloat r1 = laneSelect(r0, c / q, q != (LaneFloat)(0.0f));
    *t0 = fmin(r0, r1);
    *t1 = fmax(r0, r1);
    return found;
}

/* Both roots of a t² + b t + c = 0 in ascending order (the cone's, whose a may be 0: then
 * the one root of the linear equation, where b is not 0), in the lanes that have them. */
static inline LaneInt RAY_LANE_FN(solveQuadratic)(LaneFloat a, LaneFloat b, LaneFloat c, LaneFloat* t0,
                                                  LaneFloat* t1) {
    LaneInt linear = a == (LaneFloat)(0.0f);
    LaneFloat halfB = 0.5f * b;
    LaneInt found = RAY_LANE_FN(closestApproachRoots)(a, halfB, c, halfB * halfB - a * c, t0, t1);
    if (!laneAny(linear)) return found;
    LaneFloat root = -c / b;
    *t0 = laneSelect(*t0, root, linear);
    *t1 = laneSelect(*t1, root, linear);
    return laneSelect(found, b != (LaneFloat)(0.0f), linear);
}

/* The cube's slabs on one axis, as in the reference (host/reference/shapes.cpp): inside the
 * cube the ray runs from the largest entering to the smallest leaving plane distance. Faces
 * are numbered as parts: axis·2 for the +0.5 plane, axis·2 + 1 for the −0.5 plane. Returns
 * the lanes that miss on this axis (parallel to the slab and outside it); a parallel lane
 * inside it leaves the distances as they were. */
static inline LaneInt RAY_LANE_FN(cubeSlab)(LaneFloat oa, LaneFloat da, int axis, LaneFloat* tEnter,
                                            LaneInt* enterFace, LaneFloat* tLeave, LaneInt* leaveFace) {
    LaneInt parallel = da == (LaneFloat)(0.0f);
    LaneInt outside = parallel & ((oa < (LaneFloat)(-0.5f)) | (oa > (LaneFloat)(0.5f)));
    LaneFloat inverse = 1.0f / da;
    LaneFloat tLow = (-0.5f - oa) * inverse, tHigh = (0.5f - oa) * inverse;
    LaneInt swap = tLow > tHigh;
    LaneFloat low = laneSelect(tLow, tHigh, swap), high = laneSelect(tHigh, tLow, swap);
    LaneInt lowFace = laneSelect((LaneInt)(axis * 2 + 1), (LaneInt)(axis * 2), swap);
    LaneInt highFace = laneSelect((LaneInt)(axis * 2), (LaneInt)(axis * 2 + 1), swap);
    LaneInt enters = laneNot(parallel) & (low > *tEnter), leaves = laneNot(parallel) & (high < *tLeave);
    *tEnter = laneSelect(*tEnter, low, enters);
    *enterFace = laneSelect(*enterFace, lowFace, enters);
    *tLeave = laneSelect(*tLeave, high, leaves);
    *leaveFace = laneSelect(*leaveFace, highFace, leaves);
    return outside;
}

static inline void RAY_LANE_FN(intersectCube)(LaneVec3 o, LaneVec3 d, RAY_LANE_FN(ShapeHit) * h) {
    LaneFloat tEnter = (LaneFloat)(-RAY_INFINITY), tLeave = (LaneFloat)(RAY_INFINITY);
    LaneInt enterFace = (LaneInt)(0), leaveFace = (LaneInt)(0);
    LaneInt missed = RAY_LANE_FN(cubeSlab)(o.x, d.x, 0, &tEnter, &enterFace, &tLeave, &leaveFace);
    missed |= RAY_LANE_FN(cubeSlab)(o.y, d.y, 1, &tEnter, &enterFace, &tLeave, &leaveFace);
    missed |= RAY_LANE_FN(cubeSlab)(o.z, d.z, 2, &tEnter, &enterFace, &tLeave, &leaveFace);
    /* From outside the nearest hit is where the ray enters; from inside, where it leaves. */
    LaneInt fromOutside = tEnter > (LaneFloat)(0.0f);
    LaneFloat t = laneSelect(tLeave, tEnter, fromOutside);
    LaneInt face = laneSelect(leaveFace, enterFace, fromOutside);
    LaneFloat sign = laneSelect((LaneFloat)(1.0f), (LaneFloat)(-1.0f), (face & 1) != 0);
    LaneFloat zero = (LaneFloat)(0.0f);
    LaneVec3 normal = laneVec3(laneSelect(zero, sign, face < 2), laneSelect(zero, sign, (face >= 2) & (face < 4)),
                               laneSelect(zero, sign, face >= 4));
    RAY_LANE_FN(considerHit)(laneNot(missed) & laneNot(tEnter > tLeave), t, face, normal, h);
}

static inline void RAY_LANE_FN(intersectSphere)(LaneVec3 o, LaneVec3 d, RAY_LANE_FN(ShapeHit) * h) {
    LaneFloat a = laneDot(d, d), halfB = laneDot(o, d);
    LaneVec3 f = laneAlong(o, -(halfB / a), d); /* the ray's closest approach to the centre */
    LaneFloat t0, t1;
    LaneInt found = RAY_LANE_FN(closestApproachRoots)(a, halfB, laneDot(o, o) - 0.25f, a * (0.25f - laneDot(f, f)),
                                                      &t0, &t1);
    if (!laneAny(found)) return;
    LaneFloat t = laneSelect(t1, t0, t0 > (LaneFloat)(0.0f));
    RAY_LANE_FN(considerHit)(found, t, (LaneInt)(PART_SIDE), laneAlong(o, t, d), h);
}

/* A cap of radius 0.5 in the plane y = capY. */
static inline void RAY_LANE_FN(intersectCap)(LaneVec3 o, LaneVec3 d, float capY, int capPart,
                                             RAY_LANE_FN(ShapeHit) * h) {
    LaneFloat t = (capY - o.y) / d.y;
    LaneVec3 p = laneAlong(o, t, d);
    LaneInt inside = (d.y != (LaneFloat)(0.0f)) & (p.x * p.x + p.z * p.z <= (LaneFloat)(0.25f));
    LaneVec3 normal = laneVec3((LaneFloat)(0.0f), (LaneFloat)(capY > 0.0f ? 1.0f : -1.0f), (LaneFloat)(0.0f));
    RAY_LANE_FN(considerHit)(inside, t, (LaneInt)(capPart), normal, h);
}

/* A root of the cylinder's or the cone's side counts, in the lanes of `found`, where it lies
 * between the caps. */
static inline void RAY_LANE_FN(considerSideRoot)(LaneInt found, LaneVec3 o, LaneVec3 d, LaneFloat t, bool cone,
                                                 RAY_LANE_FN(ShapeHit) * h) {
    LaneVec3 p = laneAlong(o, t, d);
    LaneInt between = found & (p.y >= (LaneFloat)(-0.5f)) & (p.y <= (LaneFloat)(0.5f));
    LaneFloat ny = cone ? 0.25f * (0.5f - p.y) : (LaneFloat)(0.0f);
    RAY_LANE_FN(considerHit)(between, t, (LaneInt)(PART_SIDE), laneVec3(p.x, ny, p.z), h);
}

static inline void RAY_LANE_FN(intersectCylinder)(LaneVec3 o, LaneVec3 d, RAY_LANE_FN(ShapeHit) * h) {
    LaneFloat a = d.x * d.x + d.z * d.z; /* 0 for a ray along the axis: the side is missed */
    LaneFloat halfB = o.x * d.x + o.z * d.z;
    LaneFloat fx = o.x - (halfB / a) * d.x, fz = o.z - (halfB / a) * d.z; /* closest approach to the axis */
    LaneFloat t0, t1;
    LaneInt found = (a > (LaneFloat)(0.0f)) &
                    RAY_LANE_FN(closestApproachRoots)(a, halfB, o.x * o.x + o.z * o.z - 0.25f,
                                                      a * (0.25f - (fx * fx + fz * fz)), &t0, &t1);
    if (laneAny(found)) {
        RAY_LANE_FN(considerSideRoot)(found, o, d, t0, false, h);
        RAY_LANE_FN(considerSideRoot)(found, o, d, t1, false, h);
    }
    RAY_LANE_FN(intersectCap)(o, d, 0.5f, PART_TOP, h);
    RAY_LANE_FN(intersectCap)(o, d, -0.5f, PART_BOTTOM, h);
}

/* Side: x² + z² = ((0.5 − y) / 2)², the radius shrinking from 0.5 at the base to 0 at the
 * apex (0, 0.5, 0). */
static inline void RAY_LANE_FN(intersectCone)(LaneVec3 o, LaneVec3 d, RAY_LANE_FN(ShapeHit) * h) {
    LaneFloat k = 0.5f - o.y; /* (0.5 − y) at the origin; along the ray it is k − t·d.y */
    LaneFloat a = d.x * d.x + d.z * d.z - 0.25f * d.y * d.y;
    LaneFloat b = 2.0f * (o.x * d.x + o.z * d.z) + 0.5f * k * d.y;
    LaneFloat c = o.x * o.x + o.z * o.z - 0.25f * k * k;
    LaneFloat t0, t1;
    LaneInt found = RAY_LANE_FN(solveQuadratic)(a, b, c, &t0, &t1);
    if (laneAny(found)) {
        RAY_LANE_FN(considerSideRoot)(found, o, d, t0, true, h);
        RAY_LANE_FN(considerSideRoot)(found, o, d, t1, true, h);
    }
    RAY_LANE_FN(intersectCap)(o, d, -0.5f, PART_BOTTOM, h);
}

/* Intersects the convex shape of type `type` (convexShape) in object space. Inlined on every
 * device: one ray's intersectPrimitive has switched on the type already, and as a call of
 * its own on a CPU it switched again (docs/performance.md, "One source for the shapes"). */
static inline __attribute__((always_inline)) void RAY_LANE_FN(intersectConvexShape)(int type, LaneVec3 o, LaneVec3 d,
                                                                                    RAY_LANE_FN(ShapeHit) * h) {
    switch (type) {
        case RAY_PRIM_CUBE: RAY_LANE_FN(intersectCube)(o, d, h); break;
        case RAY_PRIM_SPHERE: RAY_LANE_FN(intersectSphere)(o, d, h); break;
        case RAY_PRIM_CYLINDER: RAY_LANE_FN(intersectCylinder)(o, d, h); break;
        case RAY_PRIM_CONE: RAY_LANE_FN(intersectCone)(o, d, h); break;
        default: break;
    }
}

#endif /* RAY_LANE_VOCABULARY */
