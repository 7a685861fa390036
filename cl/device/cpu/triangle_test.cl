/* How a CPU tests a mesh leaf's triangles for one ray (intersectLeafTriangles, whose caller
 * is intersectMesh, cl/geometry/torus_mesh.cl): a record's four at once, lane k triangle k,
 * in float4s (intersectTriangleRecordsQuad, cl/geometry/triangle.cl). A GPU tests them one
 * at a time (cl/device/gpu/triangle_test.cl). */
#ifdef RAY_DEVICE_CPU

static inline void intersectLeafTriangles(__global const RayTriangle4* records, int first, int count, float3 o,
                                          float3 d, TriangleHit* h) {
    intersectTriangleRecordsQuad(records, first, count, o, d, h);
}

#endif
