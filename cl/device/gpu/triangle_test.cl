/* How a GPU tests a mesh leaf's triangles for one ray (intersectLeafTriangles, whose caller
 * is intersectMesh, cl/geometry/torus_mesh.cl): one at a time, in floats, as it tests a
 * node's boxes (cl/device/gpu/box_test.cl): a float4 is four of a work-item's registers, and
 * a record's four triangles at once would hold 48 of them. A CPU tests the four at once
 * (cl/device/cpu/triangle_test.cl). */
#ifndef RAY_DEVICE_CPU

static inline void intersectLeafTriangles(__global const RayTriangle4* records, int first, int count, float3 o,
                                          float3 d, TriangleHit* h) {
    intersectTriangleSlots(records, first, count, o, d, h);
}

#endif
