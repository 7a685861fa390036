/* A ray, the hit a trace finds, and what the intersectors share, for every device.
 *
 * Primitives are intersected in object space: the world ray is carried into the unit
 * primitive's space by its world-to-object transform without renormalizing the direction,
 * so the parameter t means the same distance along the ray in both spaces and hits of
 * different primitives compare directly.
 *
 * No fast-math anywhere in the kernel: the slab tests rely on IEEE infinities, the torus's
 * root isolation on exact comparisons. */

#define RAY_INFINITY INFINITY

typedef struct {
    float3 origin;
    float3 direction; /* unit length in world space */
    float time;       /* shutter time of the ray's camera sample (motion blur); 0: the scene at rest */
} Ray;

/* Which part of a primitive was hit; decides the texture mapping (SPEC §5). */
#define PART_SIDE 0
#define PART_TOP 1    /* +y cap (cylinder) */
#define PART_BOTTOM 2 /* -y cap (cylinder, cone) */
/* Cube faces: 0..5 = +x, -x, +y, -y, +z, -z. */

/* Whether primitives of type `type` are the convex unit shapes (cube, sphere, cylinder, cone:
 * intersectConvexShape, cl/geometry/shapes.cl), those a csg object combines and a packet is
 * intersected with at once. */
static inline bool convexShape(int type) {
    return type == RAY_PRIM_CUBE || type == RAY_PRIM_SPHERE || type == RAY_PRIM_CYLINDER || type == RAY_PRIM_CONE;
}

/* The nearest hit so far of a ray. Hits at exactly the same distance (coplanar faces) go to
 * the primitive listed later in the scene (the higher order: hitLimit, cl/geometry/shapes.cl),
 * as in the reference renderer, so that the image does not depend on the order in which a
 * walk visits them. */
typedef struct {
    float t;
    int primitive;   /* position in the primitive buffer, -1 for a miss */
    int part;
    float3 objectPoint;
    float3 objectNormal; /* outward, unnormalized */
    float2 barycentric;  /* meshes: the weights of the triangle's corners 1 and 2 (part: the triangle) */
    int order;           /* the hit primitive's RayPrimitive.order */
} Hit;

/* 1/d with exact zeros replaced by a tiny signed value, so that no 0·∞ NaN reaches a slab
 * test (an empty child's ±1e30 bounds then give huge but ordered distances). */
static inline float3 safeInverse(float3 d) {
    const float tiny = 1e-20f;
    return (float3)(1.0f / (fabs(d.x) > tiny ? d.x : copysign(tiny, d.x)),
                    1.0f / (fabs(d.y) > tiny ? d.y : copysign(tiny, d.y)),
                    1.0f / (fabs(d.z) > tiny ? d.z : copysign(tiny, d.z)));
}

/* The slab test: the distance at which a ray enters the box [minX, maxX] × [minY, maxY] ×
 * [minZ, maxZ] within (0, tMax), +infinity where it misses or where the box is not
 * `present`, given the ray's origin and safe inverse direction (safeInverse). One definition
 * for any float type FloatN (IntN its int type), whose lanes are the children of a wide node
 * tested at once (a CPU's walk a ray at a time; present where a child exists), the rays of a
 * packet (the packet walk), or neither (a GPU's, a box at a time; present 1, true):
 * RAY_DEFINE_SLAB_ENTRY defines the function `name` for one such type, and each of its uses
 * is the same arithmetic, operation for operation, so the same bits.
 *
 * Its minimum and maximum are of operands that are never NaN (safeInverse): OpenCL's fmin
 * and fmax must return the operand that is not NaN, which costs a compare-unordered and a
 * blend a call on CPUs, where a select compiles to one vminps/vmaxps. */
#define RAY_DEFINE_SLAB_ENTRY(name, FloatN, IntN)                                                                  \
    static inline FloatN name##Min(FloatN a, FloatN b) { return select(b, a, a < b); }                           \
    static inline FloatN name##Max(FloatN a, FloatN b) { return select(b, a, a > b); }                           \
    static inline FloatN name(FloatN minX, FloatN maxX, FloatN minY, FloatN maxY, FloatN minZ, FloatN maxZ,       \
                              FloatN originX, FloatN originY, FloatN originZ, FloatN inverseX, FloatN inverseY,   \
                              FloatN inverseZ, FloatN tMax, IntN present) {                                       \
        FloatN tx0 = (minX - originX) * inverseX, tx1 = (maxX - originX) * inverseX;                              \
        FloatN ty0 = (minY - originY) * inverseY, ty1 = (maxY - originY) * inverseY;                              \
        FloatN tz0 = (minZ - originZ) * inverseZ, tz1 = (maxZ - originZ) * inverseZ;                              \
        FloatN tNear = name##Max(name##Max(name##Min(tx0, tx1), name##Min(ty0, ty1)),                             \
                                 name##Max(name##Min(tz0, tz1), (FloatN)(0.0f)));                                 \
        FloatN tFar = name##Min(name##Min(name##Max(tx0, tx1), name##Max(ty0, ty1)),                              \
                                name##Min(name##Max(tz0, tz1), tMax));                                            \
        return select((FloatN)(RAY_INFINITY), tNear, (tNear <= tFar) & present);                                  \
    }
