/* Reading a mesh's triangle records (RayTriangle4, cl/shared_types.h): triangle `slot` is
 * lane slot % 4 of record slot / 4. The tests that read them: cl/geometry/triangle.cl. */

/* Lane `lane` (0..3) of a float4 in global memory. */
static inline float recordLane(__global const float4* v, int lane) { return ((__global const float*)v)[lane]; }

/* Triangle `slot`'s corner p0 and edges e1, e2. */
static inline void triangleOfSlot(__global const RayTriangle4* records, int slot, float3* p0, float3* e1, float3* e2) {
    __global const RayTriangle4* r = &records[slot >> 2];
    const int k = slot & 3;
    *p0 = (float3)(recordLane(&r->p0x, k), recordLane(&r->p0y, k), recordLane(&r->p0z, k));
    *e1 = (float3)(recordLane(&r->e1x, k), recordLane(&r->e1y, k), recordLane(&r->e1z, k));
    *e2 = (float3)(recordLane(&r->e2x, k), recordLane(&r->e2y, k), recordLane(&r->e2z, k));
}

/* The outward object normal (unnormalized) of a hit on triangle `slot`: its face normal. */
static inline float3 triangleFaceNormal(__global const RayTriangle4* records, int slot) {
    float3 p0, e1, e2;
    triangleOfSlot(records, slot, &p0, &e1, &e2);
    return cross(e1, e2);
}
