/* The torus and triangle meshes (SPEC §2), in object space like the other primitives,
 * a ray at a time; declared in cl/geometry/intersect.cl, which dispatches to them. */

#define TORUS_MAJOR RAY_TORUS_MAJOR_RADIUS
#define TORUS_MINOR RAY_TORUS_MINOR_RADIUS

/* Derivative `order` (0 to 3) of the monic quartic s⁴ + c.w s³ + c.z s² + c.y s + c.x. */
static inline float quarticDerivative(float4 c, int order, float s) {
    switch (order) {
        case 0: return (((s + c.w) * s + c.z) * s + c.y) * s + c.x;
        case 1: return ((4.0f * s + 3.0f * c.w) * s + 2.0f * c.z) * s + c.y;
        case 2: return (12.0f * s + 6.0f * c.w) * s + 2.0f * c.z;
        default: return 24.0f * s + 6.0f * c.w;
    }
}

/* The one root of derivative `order` in [a, b], where it is monotone and changes sign
 * (f(a) = fa): bisection until the interval cannot shrink in float. */
float bisectQuartic(float4 c, int order, float a, float b, float fa) {
    for (int i = 0; i < 64; ++i) {
        float mid = 0.5f * (a + b);
        if (mid <= a || mid >= b) break;
        float fm = quarticDerivative(c, order, mid);
        if (fm == 0.0f) return mid;
        if ((fm < 0.0f) == (fa < 0.0f)) {
            a = mid;
            fa = fm;
        } else {
            b = mid;
        }
    }
    return 0.5f * (a + b);
}

/* Isolation (host/reference/polynomial.cpp does the same in double): given breakpoints b[0..n-1]
 * (the interval's ends and, between them, the roots of derivative order + 1, ascending),
 * derivative `order` is monotone between neighbours; writes its roots into out (between
 * the ends out[0] = b[0] and out[count - 1] = b[n - 1], which the caller's next level
 * needs) and returns the new breakpoint count. */
int quarticBreakpoints(float4 c, int order, const float* b, int n, float* out) {
    int count = 0;
    out[count++] = b[0];
    float fLo = quarticDerivative(c, order, b[0]);
    for (int i = 0; i + 1 < n; ++i) {
        float fB = quarticDerivative(c, order, b[i + 1]);
        if (i + 2 < n && fB == 0.0f) out[count++] = b[i + 1];
        else if (fLo != 0.0f && fB != 0.0f && (fLo < 0.0f) != (fB < 0.0f))
            out[count++] = bisectQuartic(c, order, b[i], b[i + 1], fLo);
        fLo = fB;
    }
    out[count++] = b[n - 1];
    return count;
}

/* Ray–torus: (|p|² + R² − r²)² = 4R²(x² + z²). The ray is first moved to where it enters
 * the torus's bounding box and given a unit direction, so that the quartic's coefficients
 * are of the torus's own size (in the direct form, a distant origin's magnitude, raised to
 * the fourth power, swamps the float mantissa). Its roots on the box's span are then
 * isolated through the derivatives' roots and bisected: robust for grazing rays (two close
 * roots) and rays through the hole (none) alike. */
RAY_INLINED_ON_GPU void intersectTorus(float3 o, float3 d, float* best, int* part, float3* normal) {
    float scale = length(d);
    if (scale == 0.0f) return;
    float3 u = d / scale;
    /* Slabs of the box [±(R + r), ±r, ±(R + r)], a little padded; s = t·|d|. */
    float3 halfSize = (float3)(TORUS_MAJOR + TORUS_MINOR, TORUS_MINOR, TORUS_MAJOR + TORUS_MINOR) * 1.001f;
    float3 inverse = safeInverse(u);
    float3 s0 = (-halfSize - o) * inverse, s1 = (halfSize - o) * inverse;
    float3 sNear = fmin(s0, s1), sFar = fmax(s0, s1);
    float sLo = fmax(fmax(sNear.x, sNear.y), fmax(sNear.z, 0.0f));
    float sHi = fmin(fmin(sFar.x, sFar.y), fmin(sFar.z, *best * scale));
    if (!(sLo <= sHi)) return;
    float3 q = o + sLo * u;

    const float R2 = TORUS_MAJOR * TORUS_MAJOR;
    float k = dot(q, q) + R2 - TORUS_MINOR * TORUS_MINOR, m = dot(q, u);
    float radialD = u.x * u.x + u.z * u.z, radialOD = q.x * u.x + q.z * u.z, radialO = q.x * q.x + q.z * q.z;
    float4 c = (float4)(k * k - 4.0f * R2 * radialO, 4.0f * m * k - 8.0f * R2 * radialOD,
                        4.0f * m * m + 2.0f * k - 4.0f * R2 * radialD, 4.0f * m);
    float span = sHi - sLo;

    /* Breakpoints, level by level: the third derivative's root, then the second's, the
     * first's; between the last breakpoints the quartic itself is monotone. */
    float b3[3], b2[4], b1[5];
    int n3 = 0;
    b3[n3++] = 0.0f;
    float apex = -0.25f * c.w;
    if (apex > 0.0f && apex < span) b3[n3++] = apex;
    b3[n3++] = span;
    int n2 = quarticBreakpoints(c, 2, b3, n3, b2);
    int n1 = quarticBreakpoints(c, 1, b2, n2, b1);

    /* The first root of the quartic beyond s = 0 (t > 0). */
    float fLo = quarticDerivative(c, 0, b1[0]);
    float root = -1.0f;
    for (int i = 0; i + 1 < n1 && root < 0.0f; ++i) {
        float fB = quarticDerivative(c, 0, b1[i + 1]);
        if (fB == 0.0f) root = b1[i + 1];
        else if (fLo != 0.0f && (fLo < 0.0f) != (fB < 0.0f)) root = bisectQuartic(c, 0, b1[i], b1[i + 1], fLo);
        if (root >= 0.0f && !(sLo + root > 0.0f)) root = -1.0f; /* at the origin itself */
        fLo = fB;
    }
    if (root < 0.0f) return;
    float t = (sLo + root) / scale;
    if (!(t > 0.0f && t < *best)) return;
    float3 p = q + root * u;
    float radial = sqrt(p.x * p.x + p.z * p.z);
    float3 ring = radial > 0.0f ? (float3)(p.x, 0.0f, p.z) * (TORUS_MAJOR / radial) : (float3)(TORUS_MAJOR, 0.0f, 0.0f);
    *best = t;
    *part = PART_SIDE;
    *normal = p - ring; /* from the nearest point of the ring: outward */
}

/* The torus's v (SPEC §5): the angle around the tube / 2π, 0 on the outer equator,
 * growing upward on the outside. */
static inline float torusV(float3 p) {
    float radial = sqrt(p.x * p.x + p.z * p.z);
    float v = atan2(p.y, radial - TORUS_MAJOR) / (2.0f * M_PI_F);
    return v - floor(v);
}

/* The mesh's own BVH (two-level: instances above, one tree per mesh below, the triangles
 * stored once however many instances use them), walked as traceBvh walks the scene's; its
 * nodes live in the same node buffer from `root` on, its leaves' links are slots of the
 * triangle records (RayTriangle4), tested as the device tests them (intersectLeafTriangles).
 * Its stack is the scene walk's `spareCount` entries from `spare` on (BvhStack,
 * cl/traversal/wide_walk.cl): it starts empty there and is empty again when the walk ends, an
 * overflow included (afterOverflow), so the scene walk's own entries below are never touched.
 * The search h goes on from where it stands (takesTriangleHit, cl/geometry/triangle.cl, whose
 * tie rule makes the triangle found independent of the order of the walk): a box entered
 * exactly at the nearest hit so far is visited (enteredBy), since it may hold a tie. */
RAY_INLINED_ON_GPU
void intersectMesh(__global const RayWideBvhNode* nodes, __global const RayTriangle4* triangles, int root, float3 o,
                   float3 d, BvhStackEntry* spare, int spareCount, TriangleHit* h) {
    float3 inverseDirection = safeInverse(d);
    BvhStack stack = emptyBvhStack(spare, spareCount);
    int next = root;
    do {
        NodeChildren children = next == RAY_WALK_EVERY_PRIMITIVE ? everyPrimitiveUnder(nodes, root)
                                                                 : testChildren(&nodes[next], o, inverseDirection, h->best);
        InnerChildren inner;
        inner.count = 0;
        float limit = h->best; /* read again only after a leaf's triangles, as traceBvh does */
        for (int c = 0; c < 4; ++c) {
            if (!enteredBy(children.entry[c], limit)) continue;
            const int first = children.index[c], count = children.count[c];
            if (count > 0) {
                intersectLeafTriangles(triangles, first, count, o, d, h);
                limit = h->best;
            } else {
                addInnerChild(&inner, first, children.entry[c], true);
            }
        }
        next = afterOverflow(nextNode(&inner, &stack, limit), &stack);
    } while (next != -1);
}

/* The shading normal of a mesh hit (object space): the corners' normals (the file's vn, or
 * the face normal where it gave none) interpolated at the hit. */
static inline float3 meshShadingNormal(__global const RayTriangleShading* shading, int triangle, float2 b) {
    __global const RayTriangleShading* s = &shading[triangle];
    const float3 n0 = vload3(0, s->normal0);
    float3 n = (1.0f - b.x - b.y) * n0 + b.x * vload3(0, s->normal1) + b.y * vload3(0, s->normal2);
    return dot(n, n) > 0.0f ? n : n0;
}

/* The texture coordinates of a mesh hit: the corners' vt interpolated, (0, 0) without. */
static inline float2 meshUv(__global const RayTriangleShading* shading, int triangle, float2 b) {
    __global const RayTriangleShading* s = &shading[triangle];
    return (1.0f - b.x - b.y) * s->uv0 + b.x * s->uv1 + b.y * s->uv2;
}
