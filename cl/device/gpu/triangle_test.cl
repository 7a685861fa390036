/* How a GPU tests a mesh leaf's triangles for one ray (intersectLeafTriangles, whose caller
 * is intersectMesh, cl/geometry/torus_mesh.cl): one at a time, in floats, as it tests a
 * node's boxes (cl/device/gpu/box_test.cl): a float4 is four of a work-item's registers, and
 * a record's four triangles at once would hold 48 of them. A CPU tests the four at once
 * (cl/device/cpu/triangle_test.cl). */
#ifndef RAY_DEVICE_CPU

/* The triangles in slots [first, first + count) (a leaf, or on a walk's overflow every leaf
 * under a node: cl/traversal/wide_walk.cl leafRange), in slot order. */
static inline void intersectLeafTriangles(__global const RayTriangle4* records, int first, int count, float3 o,
                                          float3 d, TriangleHit* h) {
    for (int slot = first; slot < first + count; ++slot) {
        float3 p0, e1, e2;
        triangleOfSlot(records, slot, &p0, &e1, &e2);
        intersectTriangle(p0, e1, e2, slot, o, d, h);
    }
}

#endif
