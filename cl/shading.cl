/* Texture mapping (SPEC §5) and the lighting model (SPEC §4). */

/* The scene's buffers, one field each (cl/shared_types.h RAY_SCENE_BUFFERS), as renderTile
 * receives them. */
#define RAY_SCENE_BUFFER_FIELD(Type, name, what) __global const Type* name;
typedef struct {
    RAY_SCENE_BUFFERS(RAY_SCENE_BUFFER_FIELD)
} SceneBuffers;
#undef RAY_SCENE_BUFFER_FIELD

/* What one work-item carries while it traces its pixel: rays counted by kind (summed on
 * the host from one record per pixel), and the number of the pixel's next sample, which
 * seeds its random numbers (samples are numbered in the order the sampling pattern takes
 * them, as the reference renderer does). */
typedef struct {
    uint primary, shadow, secondary;
    uint pixel, nextSample;
    uint sample; /* the number of the sample being traced: area lights draw from it */
    float time;  /* its shutter time in [0, 1] (motion blur) */
} PixelTrace;

static inline float fractional(float x) { return x - floor(x); }

/* u of the sphere, and of the sides of the cylinder and cone: grows left to right seen
 * from outside, seam on the +x side. */
static inline float aroundY(float3 p) {
    return fractional(atan2(-p.z, p.x) / (2.0f * M_PI_F));
}

/* The cube's face mapping; the cylinder and cone caps use its ±y faces. */
static inline float2 cubeFaceUv(int face, float3 p) {
    switch (face) {
        case 0: return (float2)(0.5f - p.z, p.y + 0.5f); /* +x */
        case 1: return (float2)(p.z + 0.5f, p.y + 0.5f); /* -x */
        case 2: return (float2)(p.x + 0.5f, 0.5f - p.z); /* +y */
        case 3: return (float2)(p.x + 0.5f, p.z + 0.5f); /* -y */
        case 4: return (float2)(p.x + 0.5f, p.y + 0.5f); /* +z */
        default: return (float2)(0.5f - p.x, p.y + 0.5f); /* -z */
    }
}

static inline float2 surfaceUv(int type, int part, float3 p) {
    switch (type) {
        case RAY_PRIM_CUBE: return cubeFaceUv(part, p);
        case RAY_PRIM_SPHERE:
            return (float2)(aroundY(p), 0.5f + asin(clamp(p.y / 0.5f, -1.0f, 1.0f)) / M_PI_F);
        case RAY_PRIM_CYLINDER:
        case RAY_PRIM_CONE:
            if (part == PART_TOP) return cubeFaceUv(2, p);
            if (part == PART_BOTTOM) return cubeFaceUv(3, p);
            return (float2)(aroundY(p), p.y + 0.5f);
        case RAY_PRIM_TORUS: return (float2)(aroundY(p), torusV(p));
        default: return (float2)(0.0f, 0.0f); /* meshes: hitUv */
    }
}

static inline float3 texel(const SceneBuffers* scene, int4 info, int column, int row) {
    uchar4 c = scene->texels[info.x + row * info.y + column];
    return (float3)(c.x, c.y, c.z) * (1.0f / 255.0f);
}

/* Bilinear interpolation at continuous texel coordinates (x, y) in which integers name
 * texel corners, wrapping around (host/reference/texture_sampling.cpp bilinearAt). */
float3 bilinearAt(const SceneBuffers* scene, int4 info, float x, float y) {
    float x0f = floor(x), y0f = floor(y);
    float ax = x - x0f, ay = y - y0f;
    int x0 = ((int)x0f % info.y + info.y) % info.y, y0 = ((int)y0f % info.z + info.z) % info.z;
    int x1 = (x0 + 1) % info.y, y1 = (y0 + 1) % info.z;
    float3 top = mix(texel(scene, info, x0, y0), texel(scene, info, x1, y0), ax);
    float3 bottom = mix(texel(scene, info, x0, y1), texel(scene, info, x1, y1), ax);
    return mix(top, bottom, ay);
}

/* The color at (u, v) with the material's repeats of the image (or mipmap level) whose
 * texels start at info.x and measure info.y × info.z: nearest texel (the course's
 * behaviour) or bilinear between the four nearest texel centres, wrapping around. */
float3 sampleTextureLevel(const SceneBuffers* scene, int4 info, float2 uv, float2 repeats, bool bilinear) {
    float s = fractional(uv.x * repeats.x);
    float t = fractional(uv.y * repeats.y);
    float x = s * (float)info.y, y = (1.0f - t) * (float)info.z;
    if (!bilinear) {
        int column = clamp((int)x, 0, info.y - 1);
        int row = clamp((int)y, 0, info.z - 1);
        return texel(scene, info, column, row);
    }
    return bilinearAt(scene, info, x - 0.5f, y - 0.5f); /* integers at texel centres */
}

/* The course's filter (SPEC §5, --texture-filter course): bilinear with texel corners at
 * integer coordinates, i.e. without the half-texel shift. */
float3 sampleCourseBilinear(const SceneBuffers* scene, int textureIndex, float2 uv, float2 repeats) {
    int4 info = scene->textures[textureIndex].info;
    float s = fractional(uv.x * repeats.x);
    float t = fractional(uv.y * repeats.y);
    return bilinearAt(scene, info, s * (float)info.y, (1.0f - t) * (float)info.z);
}

/* The same on a texture's full-size image. */
float3 sampleTexture(const SceneBuffers* scene, int textureIndex, float2 uv, float2 repeats, bool bilinear) {
    return sampleTextureLevel(scene, scene->textures[textureIndex].info, uv, repeats, bilinear);
}

/* How far off the surface a secondary or shadow ray starts: an amount that grows with the
 * coordinates' magnitude so that float rounding of the hit point cannot put it back behind
 * the surface. */
static inline float surfaceClearance(float3 p, float epsilon) {
    return epsilon * (1.0f + fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z))));
}

/* Where a shadow ray starts: that clearance along the normal (facing the side the ray
 * leaves from). */
static inline float3 offsetFromSurface(float3 p, float3 normal, float epsilon) {
    return p + normal * surfaceClearance(p, epsilon);
}

/* How far along its own direction a secondary ray may start, in clearances: the bound on
 * what it can skip (a ray leaving at a grazing angle would otherwise start far away). */
#define RAY_MAX_STEP_ALONG_RAY 10.0f

/* Where a reflected or refracted ray leaving p along `direction` starts: the same clearance
 * off the surface as offsetFromSurface gives (normal: the surface's own, not one a bump map
 * tilts, facing the side the ray leaves from), reached by moving along the ray's own line
 * as far as RAY_MAX_STEP_ALONG_RAY allows, the rest along the normal. A start moved along
 * the normal alone shifts the ray sideways, clearance × tan θ where it meets the next
 * surface, and that shift adds up from bounce to bounce: between the mirrored, textured
 * cubes of the course's dof.xml (≈ 2 texels a bounce) it left 1.2% of the pixels off the
 * reference renderer's by more than 3/255. */
static inline float3 offsetAlongRay(float3 p, float3 normal, float3 direction, float epsilon) {
    float clearance = surfaceClearance(p, epsilon);
    float cosine = dot(direction, normal);
    float along = cosine > 0.0f ? fmin(clearance / cosine, RAY_MAX_STEP_ALONG_RAY * clearance) : 0.0f;
    return p + direction * along + normal * (clearance - along * cosine);
}

/* Spot light falloff: 1 inside the inner cone, 0 outside the outer, smooth between. */
static inline float spotFactor(const RayLight* light, float3 towardLight) {
    float cosTheta = dot(-towardLight, light->direction.xyz);
    float theta = acos(clamp(cosTheta, -1.0f, 1.0f));
    float outer = light->spot.z, inner = light->spot.w;
    if (theta >= outer) return 0.0f;
    if (theta <= inner) return 1.0f;
    float x = (theta - inner) / (outer - inner);
    return 1.0f - (3.0f * x * x - 2.0f * x * x * x);
}

static inline bool inShadow(const SceneBuffers* scene, float3 origin, float3 towardLight, float distance,
                     PixelTrace* counter) {
    counter->shadow++;
    Ray shadowRay = {origin, towardLight, counter->time}; /* the blockers as the camera sample sees them */
    Hit blocker;
    /* world t for every primitive, --course-meshes or not (docs/conventions.md, meshes) */
    return traceBvh(scene->nodes, scene->primitives, scene->triangles, scene->motions, shadowRay, distance, true,
                    false, &blocker);
}

/* One light (or one sample of an area light) seen from p: f_att · S · I_L · [D·max(N·L, 0)
 * + ks·Os·max(R·V, 0)^n], where the light sits at `position` (unused for a directional
 * light) and carries `intensity` (I_L, divided among an area light's samples). */
float3 lightContribution(const SceneBuffers* scene, const RayRenderParams* params, const RayLight* light,
                         float3 position, float3 intensity, float3 p, float3 shadowOrigin, float3 normal,
                         float3 towardEye, float3 diffuse, float3 specular, float shininess, PixelTrace* counter) {
    float3 towardLight;
    float distance, attenuation = 1.0f;
    if (light->info.x == RAY_LIGHT_DIRECTIONAL) {
        towardLight = -light->direction.xyz;
        distance = RAY_INFINITY;
    } else {
        float3 toLight = position - p;
        distance = length(toLight);
        towardLight = toLight / distance;
        float4 c = light->attenuation;
        attenuation = fmin(1.0f, 1.0f / (c.x + c.y * distance + c.z * distance * distance));
    }
    float nDotL = dot(normal, towardLight);
    if (nDotL <= 0.0f) return (float3)(0.0f);
    if (light->info.x == RAY_LIGHT_SPOT) {
        attenuation *= spotFactor(light, towardLight);
        if (attenuation <= 0.0f) return (float3)(0.0f);
    }
    if ((params->mode.z & RAY_FEATURE_SHADOWS) && inShadow(scene, shadowOrigin, towardLight, distance, counter))
        return (float3)(0.0f);
    float3 lit = diffuse * nDotL;
    if (specular.x > 0.0f || specular.y > 0.0f || specular.z > 0.0f) { /* pow is costly, and most course materials have no highlight */
        float3 reflected = 2.0f * nDotL * normal - towardLight;
        lit += specular * pow(fmax(dot(reflected, towardEye), 0.0f), shininess);
    }
    return attenuation * intensity * lit;
}

/* Σ over lights of f_att · S · I_L · [D·max(N·L, 0) + ks·Os·max(R·V, 0)^n] (SPEC §4); an
 * area light is the sum over its n² jittered point samples (cl/optics.cl), each with 1/n²
 * of its intensity and a shadow ray of its own. One loop over every light sample, around
 * one lightContribution call (a GPU compiler inlines each call site, shadow ray and all). */
float3 directLighting(const SceneBuffers* scene, const RayRenderParams* params, float3 p, float3 normal,
                      float3 towardEye, float3 diffuse, float3 specular, float shininess, PixelTrace* counter) {
    float3 sum = (float3)(0.0f);
    float3 shadowOrigin = offsetFromSurface(p, normal, params->limits.y);
    uint seed = (uint)params->counts.w;
    for (int i = 0; i < params->counts.x; ++i) {
        RayLight light = scene->lights[i];
        bool area = light.info.x == RAY_LIGHT_AREA;
        int cells = area ? max(1, light.info.y) * max(1, light.info.y) : 1;
        float3 intensity = area ? light.color.xyz / (float)cells : light.color.xyz;
        for (int c = 0; c < cells; ++c) {
            float3 position =
                area ? areaLightPoint(&light, i, c, counter->pixel, counter->sample, seed) : light.position.xyz;
            sum += lightContribution(scene, params, &light, position, intensity, p, shadowOrigin, normal, towardEye,
                                     diffuse, specular, shininess, counter);
        }
    }
    return sum;
}
