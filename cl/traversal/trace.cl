/* traceBvh: a ray through the scene, as every caller traces it (the scene's walk itself is
 * the device's: walkScene, cl/device/gpu/walk.cl or cl/device/cpu/walk.cl). */

/* Closest hit below tMax (hit->primitive = -1 when none), or with anyHit, the first hit
 * found (shadow rays, which visit children in node order: any occluder will do).
 * Returns whether anything was hit. Leaves are intersected as their parent is visited.
 * courseMeshes: meshes keyed by t_obj (intersectPrimitive). A mesh's key can be smaller
 * than its world t, so boxes are then not pruned by distance (every box the ray enters is
 * visited; hits are still compared by key): exact, slower. A GPU walks the four-wide tree,
 * nodes, a CPU the sixteen-wide one, cpuNodes (walkScene); both find the same hit, hits
 * being ranked by distance and then by order (hitLimit) whatever the order of the walk. */
RAY_INLINED_ON_GPU bool traceBvh(__global const RayWideBvhNode* nodes, __global const RayCpuBvhNode* cpuNodes,
                                 __global const RayPrimitive* prims, __global const RayTriangle4* triangles,
                                 __global const float4* motions, Ray ray, float tMax, bool anyHit,
                                 bool courseMeshes, Hit* hit) {
    startTrace(hit, tMax);
    walkScene(nodes, cpuNodes, prims, triangles, motions, ray, safeInverse(ray.direction), anyHit, courseMeshes, hit);
    return hit->primitive >= 0;
}
