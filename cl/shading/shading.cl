/* Texture mapping (SPEC §5) and the lighting model (SPEC §4). */

/* The scene's buffers, one field each (cl/shared_types.h RAY_SCENE_BUFFERS), as renderTile
 * receives them. */
#define RAY_SCENE_BUFFER_FIELD(Type, name, what, readers) __global const Type* name;
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

static inline float3 texel(const SceneBuffers* scene, RayTexture image, int column, int row) {
    uchar4 c = scene->texels[image.offset + row * image.width + column];
    return (float3)(c.x, c.y, c.z) * (1.0f / 255.0f);
}

/* Bilinear interpolation at continuous texel coordinates (x, y) in which integers name
 * texel corners, wrapping around (host/reference/texture_sampling.cpp bilinearAt). */
float3 bilinearAt(const SceneBuffers* scene, RayTexture image, float x, float y) {
    float x0f = floor(x), y0f = floor(y);
    float ax = x - x0f, ay = y - y0f;
    int x0 = ((int)x0f % image.width + image.width) % image.width;
    int y0 = ((int)y0f % image.height + image.height) % image.height;
    int x1 = (x0 + 1) % image.width, y1 = (y0 + 1) % image.height;
    float3 top = mix(texel(scene, image, x0, y0), texel(scene, image, x1, y0), ax);
    float3 bottom = mix(texel(scene, image, x0, y1), texel(scene, image, x1, y1), ax);
    return mix(top, bottom, ay);
}

/* The color at (u, v) with the material's repeats of an image (a texture, or one of its
 * mipmap levels): nearest texel (the course's behaviour) or bilinear between the four nearest
 * texel centres, wrapping around. */
float3 sampleTextureLevel(const SceneBuffers* scene, RayTexture image, float2 uv, float2 repeats, bool bilinear) {
    float s = fractional(uv.x * repeats.x);
    float t = fractional(uv.y * repeats.y);
    float x = s * (float)image.width, y = (1.0f - t) * (float)image.height;
    if (!bilinear) {
        int column = clamp((int)x, 0, image.width - 1);
        int row = clamp((int)y, 0, image.height - 1);
        return texel(scene, image, column, row);
    }
    return bilinearAt(scene, image, x - 0.5f, y - 0.5f); /* integers at texel centres */
}

/* The course's filter (SPEC §5, --texture-filter course): bilinear with texel corners at
 * integer coordinates, i.e. without the half-texel shift. */
float3 sampleCourseBilinear(const SceneBuffers* scene, int textureIndex, float2 uv, float2 repeats) {
    RayTexture image = scene->textures[textureIndex];
    float s = fractional(uv.x * repeats.x);
    float t = fractional(uv.y * repeats.y);
    return bilinearAt(scene, image, s * (float)image.width, (1.0f - t) * (float)image.height);
}

/* The same on a texture's full-size image. */
float3 sampleTexture(const SceneBuffers* scene, int textureIndex, float2 uv, float2 repeats, bool bilinear) {
    return sampleTextureLevel(scene, scene->textures[textureIndex], uv, repeats, bilinear);
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
 * surface, and that shift adds up from bounce to bounce until, between mirrored textured
 * surfaces, pixels land texels away from the reference renderer's. */
static inline float3 offsetAlongRay(float3 p, float3 normal, float3 direction, float epsilon) {
    float clearance = surfaceClearance(p, epsilon);
    float cosine = dot(direction, normal);
    float along = cosine > 0.0f ? fmin(clearance / cosine, RAY_MAX_STEP_ALONG_RAY * clearance) : 0.0f;
    return p + direction * along + normal * (clearance - along * cosine);
}

/* Spot light falloff: 1 inside the inner cone, 0 outside the outer, smooth between. */
static inline float spotFactor(__global const RayLight* light, float3 towardLight) {
    float cosTheta = dot(-towardLight, light->direction.xyz);
    float theta = acos(clamp(cosTheta, -1.0f, 1.0f));
    float outer = light->outerAngle, inner = light->innerAngle;
    if (theta >= outer) return 0.0f;
    if (theta <= inner) return 1.0f;
    float x = (theta - inner) / (outer - inner);
    return 1.0f - (3.0f * x * x - 2.0f * x * x * x);
}

/* Direct lighting, Σ over lights of f_att · S · I_L · [D·max(N·L, 0) + ks·Os·max(R·V, 0)^n]
 * (SPEC §4), where an area light is the sum over its n² jittered point samples
 * (cl/shading/optics.cl), each with 1/n² of its intensity and a shadow ray of its own: a walk over
 * the light samples seen from one shading point that hands out one shadow ray at a time,
 * so that shadeFrame traces them all at its one trace site (see there). The caller starts it
 * (startLights), asks for each sample's shadow ray (nextShadowRay) and hands back the
 * samples nothing blocks (addUnblockedSample); `sum` then holds the direct lighting. */
typedef struct {
    /* the shading point */
    float3 p, normal, towardEye, diffuse, specular;
    float shininess;
    bool highlight; /* some specular channel above 0: pow is costly, and most course materials have none */
    /* where the walk is: the light, the cell of its grid (an area light's n², else 1) and
     * the intensity of each of its samples (I_L, divided among an area light's samples) */
    int light, cell, cells;
    float3 intensity;
    /* the light sample whose shadow ray is out */
    float3 towardLight;
    float distance, attenuation, nDotL;
    float3 sum; /* of the samples so far, in the order the lights and cells come */
    /* where each shadow ray starts, computed once per shading point: PoCL spends more
     * instructions recomputing it for every sample than gfx906 spends scratch keeping it */
    float3 shadowOrigin;
} LightSamples;

/* Starts the walk over the lights at p, whose normal faces the viewer; epsilon: the shadow
 * rays' clearance (offsetFromSurface). */
static inline void startLights(LightSamples* s, float3 p, float3 normal, float3 towardEye, float3 diffuse,
                               float3 specular, float shininess, float epsilon) {
    s->p = p;
    s->normal = normal;
    s->towardEye = towardEye;
    s->diffuse = diffuse;
    s->specular = specular;
    s->shininess = shininess;
    s->shadowOrigin = offsetFromSurface(p, normal, epsilon);
    s->highlight = specular.x > 0.0f || specular.y > 0.0f || specular.z > 0.0f;
    s->light = -1; /* nextShadowRay starts the first light */
    s->cell = s->cells = 0;
    s->sum = (float3)(0.0f);
}

/* Starts the samples of light s->light. */
static inline void startLight(LightSamples* s, __global const RayLight* light) {
    bool area = light->type == RAY_LIGHT_AREA;
    s->cells = area ? max(1, light->areaSamples) * max(1, light->areaSamples) : 1;
    s->intensity = area ? light->color.xyz / (float)s->cells : light->color.xyz;
    s->cell = 0;
}

/* The part of one light sample's term before its shadow test: the light (or one sample of
 * an area light) sits at `position` (unused for a directional light). False when the term
 * is zero whatever blocks the light: behind the surface, or outside a spot light's cone. */
static inline bool lightFacing(LightSamples* s, __global const RayLight* light, float3 position) {
    float attenuation = 1.0f;
    if (light->type == RAY_LIGHT_DIRECTIONAL) {
        s->towardLight = -light->direction.xyz;
        s->distance = RAY_INFINITY;
    } else {
        float3 toLight = position - s->p;
        s->distance = length(toLight);
        s->towardLight = toLight / s->distance;
        attenuation = fmin(1.0f, 1.0f / (light->constantAttenuation + light->linearAttenuation * s->distance +
                                         light->quadraticAttenuation * s->distance * s->distance));
    }
    s->nDotL = dot(s->normal, s->towardLight);
    if (s->nDotL <= 0.0f) return false;
    if (light->type == RAY_LIGHT_SPOT) {
        attenuation *= spotFactor(light, s->towardLight);
        if (attenuation <= 0.0f) return false;
    }
    s->attenuation = attenuation;
    return true;
}

/* The base of the highlight's power of the light sample lightFacing took: max(R·V, 0). */
static inline float highlightBase(const LightSamples* s) {
    float3 reflected = 2.0f * s->nDotL * s->normal - s->towardLight;
    return fmax(dot(reflected, s->towardEye), 0.0f);
}

/* highlightBase(s)^n (n the shininess): pow(+0, n) is +0 for n > 0, taken without the call,
 * PoCL's costliest (addUnblockedSamples, cl/device/cpu/packet_render.cl, takes the same for a packet). */
static inline float highlightPower(float base, float shininess) {
    return base > 0.0f || shininess <= 0.0f ? pow(base, shininess) : 0.0f;
}

/* The term of the light sample lightFacing took, unblocked: f_att · S · I_L ·
 * [D·max(N·L, 0) + ks·Os·max(R·V, 0)^n], given max(R·V, 0)^n (read only with a highlight). */
static inline float3 litSampleWithPower(const LightSamples* s, float power) {
    float3 lit = s->diffuse * s->nDotL;
    if (s->highlight) lit += s->specular * power;
    return s->attenuation * s->intensity * lit;
}

/* Adds the sample whose shadow ray found no blocker, given its highlight's power (the
 * packet path takes its lanes' powers at once: cl/device/cpu/packet_render.cl). Blocked samples and
 * those lightFacing turned down add nothing: skipping them is adding +0, as the sum starts
 * at +0 and so is never −0. */
static inline void addUnblockedSampleWithPower(LightSamples* s, float power) {
    float3 term = litSampleWithPower(s, power); /* a statement of its own: not contracted into the sum */
    s->sum += term;
}

static inline void addUnblockedSample(LightSamples* s) {
    addUnblockedSampleWithPower(s, s->highlight ? highlightPower(highlightBase(s), s->shininess) : 0.0f);
}

/* Walks on to the next light sample that needs a shadow ray, lights and cells in order, and
 * gives that ray and its length (traced with world t for every primitive, --course-meshes
 * or not: docs/conventions.md, meshes); false when every sample is summed. Without shadows
 * a sample is summed at once. */
static inline bool nextShadowRay(LightSamples* s, const SceneBuffers* scene, const RayRenderParams* params,
                                 PixelTrace* counter, Ray* ray, float* tMax) {
    uint seed = (uint)params->seed;
    while (true) {
        if (s->cell == s->cells) { /* the light's samples are all summed */
            if (++s->light >= params->lightCount) return false;
            startLight(s, &scene->lights[s->light]);
        }
        __global const RayLight* light = &scene->lights[s->light];
        int c = s->cell++;
        float3 position = light->type == RAY_LIGHT_AREA
                              ? areaLightPoint(light, s->light, c, counter->pixel, counter->sample, seed)
                              : light->position.xyz;
        if (!lightFacing(s, light, position)) continue;
        if (!(params->features & RAY_FEATURE_SHADOWS)) {
            addUnblockedSample(s);
            continue;
        }
        counter->shadow++;
        ray->origin = s->shadowOrigin;
        ray->direction = s->towardLight;
        ray->time = counter->time; /* the blockers as the camera sample sees them */
        *tMax = s->distance;
        return true;
    }
}
