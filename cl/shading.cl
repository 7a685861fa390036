/* Texture mapping (SPEC §5) and the lighting model (SPEC §4). */

typedef struct {
    __global const RayBvhNode* nodes;
    __global const RayPrimitive* primitives;
    __global const RayMaterial* materials;
    __global const RayLight* lights;
    __global const RayTexture* textures;
    __global const uchar4* texels;
} SceneBuffers;

/* What one work-item carries while it traces its pixel: rays counted by kind (summed on
 * the host from one record per pixel), and the number of the pixel's next sample, which
 * seeds its random numbers (samples are numbered in the order the sampling pattern takes
 * them, as the reference renderer does). */
typedef struct {
    uint primary, shadow, secondary;
    uint pixel, nextSample;
} PixelTrace;

inline float fractional(float x) { return x - floor(x); }

/* u of the sphere, and of the sides of the cylinder and cone: grows left to right seen
 * from outside, seam on the +x side. */
inline float aroundY(float3 p) {
    return fractional(atan2(-p.z, p.x) / (2.0f * M_PI_F));
}

/* The cube's face mapping; the cylinder and cone caps use its ±y faces. */
inline float2 cubeFaceUv(int face, float3 p) {
    switch (face) {
        case 0: return (float2)(0.5f - p.z, p.y + 0.5f); /* +x */
        case 1: return (float2)(p.z + 0.5f, p.y + 0.5f); /* -x */
        case 2: return (float2)(p.x + 0.5f, 0.5f - p.z); /* +y */
        case 3: return (float2)(p.x + 0.5f, p.z + 0.5f); /* -y */
        case 4: return (float2)(p.x + 0.5f, p.y + 0.5f); /* +z */
        default: return (float2)(0.5f - p.x, p.y + 0.5f); /* -z */
    }
}

inline float2 surfaceUv(int type, int part, float3 p) {
    switch (type) {
        case RAY_PRIM_CUBE: return cubeFaceUv(part, p);
        case RAY_PRIM_SPHERE:
            return (float2)(aroundY(p), 0.5f + asin(clamp(p.y / 0.5f, -1.0f, 1.0f)) / M_PI_F);
        case RAY_PRIM_CYLINDER:
        case RAY_PRIM_CONE:
            if (part == PART_TOP) return cubeFaceUv(2, p);
            if (part == PART_BOTTOM) return cubeFaceUv(3, p);
            return (float2)(aroundY(p), p.y + 0.5f);
        default: return (float2)(0.0f, 0.0f);
    }
}

inline float3 texel(const SceneBuffers* scene, int4 info, int column, int row) {
    uchar4 c = scene->texels[info.x + row * info.y + column];
    return (float3)(c.x, c.y, c.z) * (1.0f / 255.0f);
}

/* The texture color at (u, v) with the material's repeats: nearest texel (the course's
 * behaviour) or bilinear between the four nearest texel centres, wrapping around. */
float3 sampleTexture(const SceneBuffers* scene, int textureIndex, float2 uv, float2 repeats, bool bilinear) {
    int4 info = scene->textures[textureIndex].info; /* offset, width, height */
    float s = fractional(uv.x * repeats.x);
    float t = fractional(uv.y * repeats.y);
    float x = s * (float)info.y, y = (1.0f - t) * (float)info.z;
    if (!bilinear) {
        int column = clamp((int)x, 0, info.y - 1);
        int row = clamp((int)y, 0, info.z - 1);
        return texel(scene, info, column, row);
    }
    float fx = x - 0.5f, fy = y - 0.5f;
    float x0f = floor(fx), y0f = floor(fy);
    float ax = fx - x0f, ay = fy - y0f;
    int x0 = ((int)x0f % info.y + info.y) % info.y, y0 = ((int)y0f % info.z + info.z) % info.z;
    int x1 = (x0 + 1) % info.y, y1 = (y0 + 1) % info.z;
    float3 top = mix(texel(scene, info, x0, y0), texel(scene, info, x1, y0), ax);
    float3 bottom = mix(texel(scene, info, x0, y1), texel(scene, info, x1, y1), ax);
    return mix(top, bottom, ay);
}

/* Where a secondary or shadow ray starts: off the surface along the normal (facing the
 * side the ray leaves from), by an amount that grows with the coordinates' magnitude so
 * that float rounding of the hit point cannot put it back behind the surface. */
inline float3 offsetFromSurface(float3 p, float3 normal, float epsilon) {
    float scale = 1.0f + fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z)));
    return p + normal * (epsilon * scale);
}

/* Spot light falloff: 1 inside the inner cone, 0 outside the outer, smooth between. */
inline float spotFactor(const RayLight* light, float3 towardLight) {
    float cosTheta = dot(-towardLight, light->direction.xyz);
    float theta = acos(clamp(cosTheta, -1.0f, 1.0f));
    float outer = light->spot.z, inner = light->spot.w;
    if (theta >= outer) return 0.0f;
    if (theta <= inner) return 1.0f;
    float x = (theta - inner) / (outer - inner);
    return 1.0f - (3.0f * x * x - 2.0f * x * x * x);
}

inline bool inShadow(const SceneBuffers* scene, const RayRenderParams* params, float3 origin, float3 towardLight,
                     float distance, PixelTrace* counter) {
    counter->shadow++;
    Ray shadowRay = {origin, towardLight};
    Hit blocker;
    return traceBvh(scene->nodes, scene->primitives, shadowRay, distance, true, &blocker);
}

/* Σ over lights of f_att · S · I_L · [D·max(N·L, 0) + ks·Os·max(R·V, 0)^n] (SPEC §4). */
float3 directLighting(const SceneBuffers* scene, const RayRenderParams* params, float3 p, float3 normal,
                      float3 towardEye, float3 diffuse, float3 specular, float shininess, PixelTrace* counter) {
    float3 sum = (float3)(0.0f);
    float3 shadowOrigin = offsetFromSurface(p, normal, params->limits.y);
    bool shadows = (params->mode.z & RAY_FEATURE_SHADOWS) != 0;
    bool hasSpecular = specular.x > 0.0f || specular.y > 0.0f || specular.z > 0.0f;
    for (int i = 0; i < params->counts.x; ++i) {
        RayLight light = scene->lights[i];
        float3 towardLight;
        float distance, attenuation = 1.0f;
        if (light.info.x == RAY_LIGHT_DIRECTIONAL) {
            towardLight = -light.direction.xyz;
            distance = RAY_INFINITY;
        } else {
            float3 toLight = light.position.xyz - p;
            distance = length(toLight);
            towardLight = toLight / distance;
            float4 c = light.attenuation;
            attenuation = fmin(1.0f, 1.0f / (c.x + c.y * distance + c.z * distance * distance));
        }
        float nDotL = dot(normal, towardLight);
        if (nDotL <= 0.0f) continue;
        if (light.info.x == RAY_LIGHT_SPOT) {
            attenuation *= spotFactor(&light, towardLight);
            if (attenuation <= 0.0f) continue;
        }
        if (shadows && inShadow(scene, params, shadowOrigin, towardLight, distance, counter)) continue;
        float3 lit = diffuse * nDotL;
        if (hasSpecular) { /* pow is costly, and most course materials have no highlight */
            float3 reflected = 2.0f * nDotL * normal - towardLight;
            lit += specular * pow(fmax(dot(reflected, towardEye), 0.0f), shininess);
        }
        sum += attenuation * light.color.xyz * lit;
    }
    return sum;
}
