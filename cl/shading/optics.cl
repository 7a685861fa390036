/* Refraction (SPEC §4) and area-light sampling: the geometry both renderers share. The
 * reference renderer (host/reference/reference_renderer.cpp, host/reference/optics.h) follows these functions
 * step by step, so that the kernel and the host agree sample for sample. */

/* The media a ray travels through, innermost last: the ior of each transparent object it
 * is inside of. Outside every object the medium is 1 (SPEC §4). A ray that enters a
 * transparent surface pushes that material's ior; one that leaves it pops, landing in the
 * medium that surrounded the object (so a glass ball inside a water ball works). At most
 * RAY_MAX_MEDIA levels are kept: entering a fifth nested object overwrites the innermost
 * entry. Leaving with an empty stack (a camera inside an object) leaves into air. */
#define RAY_MAX_MEDIA 4

typedef struct {
    float ior[RAY_MAX_MEDIA];
    int count;
} MediumStack;

static inline float currentIor(const MediumStack* media) { return media->count > 0 ? media->ior[media->count - 1] : 1.0f; }

/* The ior on the far side of a surface, and the stack the transmitted ray carries. */
static inline float iorBeyond(const MediumStack* media, bool entering, float materialIor, MediumStack* beyond) {
    *beyond = *media;
    if (entering) {
        if (beyond->count < RAY_MAX_MEDIA) beyond->count++;
        beyond->ior[beyond->count - 1] = materialIor;
        return materialIor;
    }
    if (beyond->count > 0) beyond->count--;
    return currentIor(beyond);
}

/* The ior on the near side: the medium the ray is in, or, for a ray leaving an object
 * that no entry recorded, the object's own. */
static inline float iorBefore(const MediumStack* media, bool entering, float materialIor) {
    return (entering || media->count > 0) ? currentIor(media) : materialIor;
}

/* Snell's law for unit direction d meeting a surface whose unit normal n faces the ray,
 * from ior n1 into ior n2: false for total internal reflection. */
static inline bool refractDirection(float3 d, float3 n, float n1, float n2, float3* transmitted) {
    float eta = n1 / n2;
    float cosIncident = -dot(d, n);
    float k = 1.0f - eta * eta * (1.0f - cosIncident * cosIncident);
    if (k < 0.0f) return false;
    *transmitted = normalize(eta * d + (eta * cosIncident - sqrt(k)) * n);
    return true;
}

/* The exact Fresnel reflectance of a dielectric interface for unpolarised light (the mean
 * of the s and p reflectances), met at cosIncident = -d·n from ior n1 into ior n2
 * (--fresnel, SPEC §4; host/reference/optics.h fresnelReflectance in double). 1 under total
 * internal reflection, by the same test as refractDirection so that the two agree, and at
 * grazing incidence; 0 where n1 = n2. A negative cosIncident (a bump map tilting the
 * shading normal past the ray) counts as its magnitude; an ior <= 0 gives 1. */
static inline float fresnelReflectance(float cosIncident, float n1, float n2) {
    if (n1 == n2) return 0.0f; /* no interface: the ray goes straight on */
    float eta = n1 / n2;
    float cosI = fabs(cosIncident);
    float k = 1.0f - eta * eta * (1.0f - cosI * cosI); /* cos²θt, as refractDirection computes it */
    if (k < 0.0f) return 1.0f;                        /* total internal reflection */
    float cosT = sqrt(k);
    float s = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    float p = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    float r = 0.5f * (s * s + p * p);
    return r <= 1.0f ? r : 1.0f; /* NaN or more than 1 only from an ior <= 0 */
}

/* Area lights (SPEC §4): the width × height rectangle centred at the light's position,
 * facing its direction d. Its width runs along U = normalize(helper × d) and its height
 * along V = d × U, where helper is the world's +y axis, or +z when d is within about 8° of
 * ±y (|d.y| > 0.99). A light pointing straight down therefore has its width along +x and
 * its height along +z. The rectangle is cut into an n × n grid (n = the light's samples per
 * side, RayLight.areaSamples); cell c (row c / n, column c % n) holds one point light, jittered
 * uniformly within the cell by random dimensions RAY_DIM_AREA(light, c, 0 and 1) of the
 * camera sample being traced, and carrying 1/n² of the light's intensity. */
#define RAY_DIM_AREA_BASE 16u
#define RAY_MAX_AREA_CELLS 1024u
#define RAY_DIM_AREA(light, cell, axis) \
    (RAY_DIM_AREA_BASE + 2u * ((uint)(light) * RAY_MAX_AREA_CELLS + (uint)(cell)) + (uint)(axis))

/* A call on PoCL (RAY_CALL_ON_CPU): inlined into the loop over the lights, the axes U and V,
 * the same for every cell, were moved out of it by LLVM and computed for every light,
 * point lights included (docs/performance.md, "The kernel on GPUs"). */
static RAY_CALL_ON_CPU float3 areaLightPoint(__global const RayLight* light, int lightIndex, int cell, uint pixel, uint sample, uint seed) {
    float3 d = light->direction.xyz;
    float3 helper = fabs(d.y) > 0.99f ? (float3)(0.0f, 0.0f, 1.0f) : (float3)(0.0f, 1.0f, 0.0f);
    float3 u = normalize(cross(helper, d));
    float3 v = cross(d, u);
    int n = max(1, light->areaSamples);
    float jx = rayRandom(pixel, sample, RAY_DIM_AREA(lightIndex, cell, 0), seed);
    float jy = rayRandom(pixel, sample, RAY_DIM_AREA(lightIndex, cell, 1), seed);
    float a = ((float)(cell % n) + jx) / (float)n - 0.5f;
    float b = ((float)(cell / n) + jy) / (float)n - 0.5f;
    return light->position.xyz + a * light->width * u + b * light->height * v;
}
