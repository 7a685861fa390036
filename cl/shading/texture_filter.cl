/* Trilinear texture filtering: the float twin of host/reference/texture_filtering.cpp, whose header
 * documents the footprint approximation (pixel spread angle × distance / cos θ, to object
 * space by the largest tangent-plane stretch of worldToObject, to texture coordinates by
 * the primitive's UV density) and the mipmap layout. */

#define MIN_FOOTPRINT_COS 0.01f

/* Texture coordinate units per object unit; meshes carry theirs per triangle. */
static inline float uvDensity(const SceneBuffers* scene, int type, int part) {
    switch (type) {
        case RAY_PRIM_SPHERE: return 2.0f / M_PI_F;
        case RAY_PRIM_TORUS: return 4.0f / M_PI_F;
        case RAY_PRIM_MESH: return scene->triangleShading[part].uvDensity;
        default: return 1.0f;
    }
}

/* The footprint's width in texture coordinates of a hit at distance t along the unit
 * direction, seen with world normal n. */
float textureFootprint(const SceneBuffers* scene, const RayRenderParams* params, __global const RayPrimitive* prim,
                       int part, float t, float3 direction, float3 n) {
    float cosTheta = fmax(fabs(dot(direction, n)), MIN_FOOTPRINT_COS);
    float3 helper = fabs(n.x) < 0.5f ? (float3)(1.0f, 0.0f, 0.0f) : (float3)(0.0f, 1.0f, 0.0f);
    float3 t1 = normalize(cross(n, helper));
    float3 t2 = cross(n, t1);
    float3 a = transformVector(prim->worldToObject, t1), b = transformVector(prim->worldToObject, t2);
    float aa = dot(a, a), bb = dot(b, b), ab = dot(a, b);
    float largest = 0.5f * (aa + bb + sqrt((aa - bb) * (aa - bb) + 4.0f * ab * ab));
    return params->pixelSpreadAngle * t / cosTheta * sqrt(largest) * uvDensity(scene, prim->type, part);
}

/* Level k of a texture: max(1, width >> k) × max(1, height >> k) texels after levels 0..k−1. */
static inline RayTexture mipLevel(RayTexture texture, int level) {
    RayTexture image = {texture.offset, texture.width, texture.height, 1};
    for (int k = 0; k < level; ++k) {
        image.offset += image.width * image.height;
        image.width = max(1, image.width >> 1);
        image.height = max(1, image.height >> 1);
    }
    return image;
}

/* Bilinear samples of levels ⌊λ⌋ and ⌊λ⌋ + 1 mixed by λ's fraction. */
float3 sampleTrilinear(const SceneBuffers* scene, int textureIndex, float2 uv, float2 repeats, float footprintUv) {
    RayTexture texture = scene->textures[textureIndex];
    float texels = footprintUv * fmax(repeats.x * (float)texture.width, repeats.y * (float)texture.height);
    float level = clamp(log2(fmax(texels, 1e-30f)), 0.0f, (float)max(0, texture.levels - 1));
    int lower = min((int)level, texture.levels - 1), upper = min(lower + 1, texture.levels - 1);
    float fraction = level - (float)lower;
    float3 fine = sampleTextureLevel(scene, mipLevel(texture, lower), uv, repeats, true);
    if (fraction <= 0.0f) return fine;
    float3 coarse = sampleTextureLevel(scene, mipLevel(texture, upper), uv, repeats, true);
    return (1.0f - fraction) * fine + fraction * coarse;
}
