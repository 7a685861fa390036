/* Bump mapping: host/reference/bump_mapping.h gives the convention (height = the map's gray level,
 * N' = normalize(N − kBumpStrength·(∂h/∂s·T + ∂h/∂t·B)), derivatives per texel by central
 * differences of bilinear reads); this is the same in float, in object space. */

#define RAY_BUMP_STRENGTH 2.0f

/* The texture coordinates of a hit (SPEC §5). */
static inline float2 hitUv(const SceneBuffers* scene, int type, const Hit* hit) {
    return type == RAY_PRIM_MESH ? meshUv(scene->triangleShading, hit->part, hit->barycentric)
                                 : surfaceUv(type, hit->part, hit->objectPoint);
}

static inline float bumpHeight(const SceneBuffers* scene, int map, float2 uv, float2 repeats) {
    float3 c = sampleTexture(scene, map, uv, repeats, true);
    return (c.x + c.y + c.z) * (1.0f / 3.0f);
}

/* The object-space direction in which u grows (SPEC §5): cube faces and caps by their
 * mapping, around the y axis for the round surfaces; meshes carry theirs per triangle. */
static inline float3 objectTangent(const SceneBuffers* scene, int type, int part, float3 p) {
    if (type == RAY_PRIM_MESH) {
        __global const RayTriangleShading* s = &scene->triangleShading[part];
        return vload3(0, s->uTangent);
    }
    int face = -1; /* cube face numbering: 0..5 = +x, -x, +y, -y, +z, -z */
    if (type == RAY_PRIM_CUBE) face = part;
    else if ((type == RAY_PRIM_CYLINDER || type == RAY_PRIM_CONE) && part != PART_SIDE) face = 2;
    switch (face) {
        case -1: return (float3)(p.z, 0.0f, -p.x); /* u = atan2(−z, x)/2π */
        case 0: return (float3)(0.0f, 0.0f, -1.0f);
        case 1: return (float3)(0.0f, 0.0f, 1.0f);
        case 5: return (float3)(-1.0f, 0.0f, 0.0f);
        default: return (float3)(1.0f, 0.0f, 0.0f);
    }
}

/* +1, or −1 on a mesh triangle whose texture coordinates are mirrored, for the shading
 * normal n (host/scene/mesh.h uvHandedness): the handedness is about the triangle's face normal,
 * and a shading normal facing the other way reverses it. */
static inline float bitangentSign(const SceneBuffers* scene, int type, int part, float3 faceNormal, float3 n) {
    if (type != RAY_PRIM_MESH) return 1.0f;
    float handedness = scene->triangleShading[part].uvHandedness;
    return dot(faceNormal, n) < 0.0f ? -handedness : handedness;
}

/* The object normal n (any length) tilted by bump map `map` at uv; B = bitangentSign · (N × T). */
float3 bumpedObjectNormal(const SceneBuffers* scene, int map, float2 uv, float2 repeats, float3 tangent,
                          float bitangentSign, float3 n) {
    n = normalize(n);
    float3 t = tangent - dot(tangent, n) * n;
    float len = length(t);
    if (!(len > 1e-6f)) return n;
    t /= len;
    float3 b = bitangentSign * cross(n, t);
    RayTexture image = scene->textures[map]; /* one texel of the repeated map, in u and v */
    float du = 1.0f / ((float)image.width * repeats.x), dv = 1.0f / ((float)image.height * repeats.y);
    float alongU = 0.5f * (bumpHeight(scene, map, uv + (float2)(du, 0.0f), repeats) -
                           bumpHeight(scene, map, uv - (float2)(du, 0.0f), repeats));
    float alongV = 0.5f * (bumpHeight(scene, map, uv + (float2)(0.0f, dv), repeats) -
                           bumpHeight(scene, map, uv - (float2)(0.0f, dv), repeats));
    return normalize(n - RAY_BUMP_STRENGTH * (alongU * t + alongV * b));
}
