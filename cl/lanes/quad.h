/* The lane vocabulary for a record's four triangles (RayTriangle4): an instance of the
 * triangle test alone (cl/geometry/triangle.cl triangleHits; the vocabulary is listed in
 * cl/lanes/one_ray.h), for one ray against a mesh leaf's triangles at once in float4s, on
 * CPU devices (a GPU tests them one by one: cl/geometry/triangle_records.cl). A lane is a
 * triangle, the ray the same in every lane, and the names end in Quad (triangleHitsQuad).
 * In GPU builds the vocabulary is left undefined, and the template compiles to nothing. */

#ifdef RAY_DEVICE_CPU

/* A point or direction a lane: one float4 a coordinate. */
typedef struct {
    float4 x, y, z;
} QuadVec3;

static inline QuadVec3 quadVec3(float4 x, float4 y, float4 z) {
    QuadVec3 v = {x, y, z};
    return v;
}

/* dot and cross as one ray's (PoCL's fuse nothing: cl/lanes/packet.h packetDot). */
static inline float4 quadDot(QuadVec3 a, QuadVec3 b) {
#pragma OPENCL FP_CONTRACT OFF
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static inline QuadVec3 quadCross(QuadVec3 a, QuadVec3 b) {
#pragma OPENCL FP_CONTRACT OFF
    return quadVec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

#define RAY_LANE_VOCABULARY
#define RAY_LANES_ARE_TRIANGLES
#define RAY_LANE_SUFFIX Quad
#define LaneFloat float4
#define LaneInt int4
#define LaneVec3 QuadVec3
#define laneVec3(x, y, z) quadVec3(x, y, z)
#define laneAny(m) any(m)
#define laneNot(m) (~(m))
#define laneDot(a, b) quadDot(a, b)
#define laneCross(a, b) quadCross(a, b)

#endif /* RAY_DEVICE_CPU */
