/* One ray against one primitive of the scene: intersectPrimitive, which every walk calls
 * (a packet walk for the shapes it does not intersect a packet at a time). */

/* Object normal to world: the transpose of world-to-object's linear part (SPEC §1: normals
 * transform by the inverse transpose of object-to-world). */
static inline float3 normalToWorld(__global const float4* m, float3 n) {
    return normalize(m[0].xyz * n.x + m[1].xyz * n.y + m[2].xyz * n.z);
}

/* The torus and meshes: cl/geometry/torus_mesh.cl. A mesh's walk keeps its stack in the
 * scene walk's unused entries, the `spareCount` from `spare` on (BvhStack), and its search
 * in h (TriangleHit, cl/geometry/triangle.cl). */
RAY_INLINED_ON_GPU void intersectTorus(float3 o, float3 d, float* best, int* part, float3* normal);
RAY_INLINED_ON_GPU
void intersectMesh(__global const RayWideBvhNode* nodes, __global const RayTriangle4* triangles, int root, float3 o,
                   float3 d, BvhStackEntry* spare, int spareCount, TriangleHit* h);

/* Constructive solid geometry: cl/geometry/csg.cl. prims is the primitive buffer (the
 * program's records are indexed in it), csg the object's own record. */
RAY_INLINED_ON_GPU
void intersectCsg(__global const RayPrimitive* prims, __global const RayPrimitive* csg, float3 origin, float3 direction,
                  Hit* hit);

/* Intersects one primitive, updating hit when it is nearer than hit->t or takes the tie
 * there (hitLimit); a mesh's walk may use the traversal stack's `spareCount` entries from
 * `spare` on (BvhStack).
 * courseMeshes (--course-meshes): a mesh's hit is keyed by t_obj = t·|M⁻¹d|/|d| (the
 * course's distance along the normalized object-space direction), which replaces hit->t
 * (so the hit point is origin + t_obj·d); the world t below which that key beats hit->t,
 * hit->t/scale, bounds the mesh's own search. objectPoint stays the true one.
 * Motion blur: at time t the instance is translated by t·motion (motions[index], world
 * space), which is the same as moving the ray's origin back by it. The host sets every
 * time to 0 when nothing moves, and then the motion buffer (a placeholder) is never read. */
static RAY_CALL_ON_CPU void intersectPrimitive(__global const RayWideBvhNode* nodes,
                                               __global const RayTriangle4* triangles, __global const float4* motions,
                                               __global const RayPrimitive* prim, int index, Ray ray,
                                               bool courseMeshes, BvhStackEntry* spare, int spareCount, Hit* hit) {
    float3 origin = ray.origin;
    if (ray.time != 0.0f) origin -= ray.time * motions[index].xyz;
    if (prim->type == RAY_PRIM_CSG) { /* its operands have transforms of their own */
        intersectCsg(prim - index, prim, origin, ray.direction, hit);
        return;
    }
    float3 o = transformPoint(prim->worldToObject, origin);
    float3 d = transformVector(prim->worldToObject, ray.direction);
    const bool keyed = courseMeshes && prim->type == RAY_PRIM_MESH;
    const float scale = keyed ? length(d) / length(ray.direction) : 1.0f;
    const float limit = keyed ? hit->t / scale : hitLimit(hit->t, hit->primitive, hit->order, prim->order);
    ShapeHit h = {limit, 0, (float3)(0.0f)};
    float2 barycentric = (float2)(0.0f);
    switch (prim->type) {
        case RAY_PRIM_TORUS: intersectTorus(o, d, &h.best, &h.part, &h.normal); break;
        case RAY_PRIM_MESH: {
            TriangleHit triangle = {h.best, -1, 0.0f, 0.0f};
            intersectMesh(nodes, triangles, prim->geometry, o, d, spare, spareCount, &triangle);
            if (triangle.part < 0) break;
            h.best = triangle.best;
            h.part = triangle.part;
            h.normal = triangleFaceNormal(triangles, triangle.part);
            barycentric = (float2)(triangle.b1, triangle.b2);
            break;
        }
        default: intersectConvexShape(prim->type, o, d, &h); break;
    }
    const float key = keyed ? h.best * scale : h.best;
    if (keyed ? (h.best < limit && key < hit->t) : h.best < limit) {
        hit->t = key;
        hit->primitive = index;
        hit->order = prim->order;
        hit->part = h.part;
        hit->objectPoint = o + h.best * d;
        hit->objectNormal = h.normal;
        hit->barycentric = barycentric;
    }
}
