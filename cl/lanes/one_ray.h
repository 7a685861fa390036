/* The lane vocabulary for one ray: the first instance of the lane templates
 * (cl/geometry/shapes.cl, cl/geometry/triangle.cl, cl/traversal/stack.cl), which every
 * device uses. A template is written once over "lanes", each lane a ray; this file makes a
 * lane the ray itself, with float for LaneFloat and the functions' plain names
 * (intersectSphere, pushNode), and
 * cl/lanes/packet.h makes the lanes the rays of a packet. The templates are compiled once
 * per vocabulary: the kernel's source list (CMakeLists.txt RAY_CL_SOURCES) names each after
 * its vocabulary, as Cycles includes kernel/bvh/traversal.h once per BVH_FUNCTION_NAME.
 *
 * The vocabulary:
 *   RAY_LANE_VOCABULARY    defined while a vocabulary is in force: the templates compile
 *   LaneFloat, LaneInt     a float and an int a lane; a comparison of LaneFloats is a LaneInt
 *                          mask, true in the lanes where it holds
 *   LaneVec3               a point or direction a lane, read by .x, .y, .z
 *   RAY_LANE_FN(name)      the instance's name of a function or type of the templates
 *   laneVec3(x, y, z)      a LaneVec3 of three LaneFloats
 *   laneSelect(a, b, m)    b in the lanes of mask m, else a (OpenCL's select, for
 *   laneSelectVec3           LaneFloat and LaneInt; the same for LaneVec3)
 *   laneAny(m)             whether some lane of m is true (a branch for every lane at once)
 *   laneNot(m)             the mask m negated
 *   laneEarlyOut(m)        whether to leave a step where no lane of m is set: one ray leaves
 *                          (a branch), a packet goes on (its selects cost less than a branch
 *                          on a mask that is seldom empty)
 *   laneAlong(o, t, d)     the LaneVec3 o + t·d (a point along a ray)
 *   laneDot(a, b)          the dot product of two LaneVec3s
 *   laneRowDot(row, v)     the dot product of a float4 row's .xyz and a LaneVec3
 *   laneCross(a, b)        the cross product a × b of two LaneVec3s
 * Every instance computes a dot and a cross product as one ray's dot and cross do, with no
 * fused multiply-add, so that a lane's result is one ray's to the bit.
 * A third vocabulary, cl/lanes/quad.h, makes the lanes a record's four triangles, for the
 * triangle test alone (RAY_LANES_ARE_TRIANGLES). */
/* A template function that some device's build leaves unused in some instance (a CPU tests a
 * leaf's triangles for one ray in the quad instance, not in one ray's): no warning for it. */
#define RAY_LANE_TEMPLATE static inline __attribute__((unused))

#define RAY_PASTE(a, b) RAY_PASTE_EXPANDED(a, b)
#define RAY_PASTE_EXPANDED(a, b) a##b
#define RAY_LANE_FN(name) RAY_PASTE(name, RAY_LANE_SUFFIX)

#define RAY_LANE_VOCABULARY
#define RAY_LANE_SUFFIX /* one ray's functions keep their plain names */
#define LaneFloat float
#define LaneInt int
#define LaneVec3 float3
#define laneVec3(x, y, z) ((float3)((x), (y), (z)))
#define laneSelect(a, b, m) ((m) ? (b) : (a))
#define laneSelectVec3(a, b, m) ((m) ? (b) : (a))
#define laneAny(m) (m)
#define laneNot(m) (!(m))
#define laneEarlyOut(m) (!(m))
#define laneAlong(o, t, d) ((o) + (t) * (d))
#define laneDot(a, b) dot(a, b)
#define laneRowDot(row, v) dot((row).xyz, v)
#define laneCross(a, b) cross(a, b)
