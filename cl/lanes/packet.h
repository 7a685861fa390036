/* The lane vocabulary for a packet: the second instance of the lane templates
 * (cl/geometry/shapes.cl, cl/geometry/triangle.cl, cl/traversal/stack.cl; the vocabulary
 * is listed in cl/lanes/one_ray.h), in a build for packets of RAY_PACKET_WIDTH rays (CPU devices:
 * cl/device/variant.h). A lane is one ray of the packet, LaneFloat an OpenCL vector of a
 * float a ray, and the functions' names end in Packet (intersectSpherePacket, pushNodePacket).
 * In other builds the vocabulary is left undefined, and the templates' last listing
 * compiles to nothing. */

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

/* A point or direction a ray of the packet, one vector a coordinate. */
typedef struct {
    PacketFloat x, y, z;
} PacketVec3;

static inline PacketVec3 packetVec3(PacketFloat x, PacketFloat y, PacketFloat z) {
    PacketVec3 v = {x, y, z};
    return v;
}

static inline PacketVec3 packetSelectVec3(PacketVec3 a, PacketVec3 b, PacketInt m) {
    return packetVec3(select(a.x, b.x, m), select(a.y, b.y, m), select(a.z, b.z, m));
}

static inline PacketVec3 packetAlong(PacketVec3 o, PacketFloat t, PacketVec3 d) {
    return packetVec3(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z);
}

/* dot(a, b) of float3s, a lane a pair: PoCL's dot is ((a.x·b.x + a.y·b.y) + a.z·b.z) with
 * no fused multiply-add, where OpenCL C would fuse this expression written out (a third of
 * the results would differ in the last bit from one ray's dot). */
static inline PacketFloat packetDot(PacketVec3 a, PacketVec3 b) {
#pragma OPENCL FP_CONTRACT OFF
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/* cross(a, b) of float3s, a lane a pair: PoCL's cross, like its dot, fuses nothing. */
static inline PacketVec3 packetCross(PacketVec3 a, PacketVec3 b) {
#pragma OPENCL FP_CONTRACT OFF
    return packetVec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

/* Whether any lane of a mask is set (-1), as OpenCL's any: PoCL 3.1 lowers any(int16) to
 * eight extract-or-branch steps, one per pair of lanes, on a path walked for every child of
 * every node. The lanes narrowed to bytes and tested as whole words compile to one
 * narrowing move and one vector test (vpmovdb, vptest with AVX-512), a short chain before
 * the branch that waits on it. */
static inline bool packetAny(PacketInt m) {
#if RAY_PACKET_WIDTH == 16
    ulong2 bytes = as_ulong2(convert_char16(m));
    return (bytes.x | bytes.y) != 0;
#elif RAY_PACKET_WIDTH == 8
    return as_ulong(convert_char8(m)) != 0;
#else
    return as_uint(convert_char4(m)) != 0;
#endif
}

#define RAY_LANE_VOCABULARY
#define RAY_LANE_SUFFIX Packet
#define LaneFloat PacketFloat
#define LaneInt PacketInt
#define LaneVec3 PacketVec3
#define laneVec3(x, y, z) packetVec3(x, y, z)
#define laneSelect(a, b, m) select(a, b, m)
#define laneSelectVec3(a, b, m) packetSelectVec3(a, b, m)
#define laneAny(m) packetAny(m)
#define laneNot(m) (~(m))
#define laneEarlyOut(m) 0
#define laneAlong(o, t, d) packetAlong(o, t, d)
#define laneDot(a, b) packetDot(a, b)
#define laneRowDot(row, v) \
    packetDot(packetVec3((PacketFloat)((row).x), (PacketFloat)((row).y), (PacketFloat)((row).z)), v)
#define laneCross(a, b) packetCross(a, b)

#endif /* RAY_PACKET_WIDTH */
