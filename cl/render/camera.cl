/* The camera (SPEC §3): a camera ray through a pixel's sample position, the lens of depth
 * of field, and a sample's shutter time. */

/* The camera ray through offset (sx, sy) of pixel (i, j) (SPEC §3). With depth of field
 * the eye moves to a point of the lens in the plane of U and V. The course's lens (SPEC §3):
 * lens = grid point (i, j) ∈ {−2..2}², the eye moving by i·a/2 along U and j·a/2 along V
 * (a/2 = the lens radius), the ray aimed where the pinhole ray meets the plane at depth
 * focallength along the look axis. --dof disk: a point of the lens disk picked by lens ∈
 * [0, 1)², the ray aimed at the point the pinhole ray reaches at the focal distance. */
static inline Ray cameraRay(const RayRenderParams* params, float i, float j, float sx, float sy, float2 lens, float time) {
    float u = 2.0f * (i + sx) / (float)params->width - 1.0f;
    float v = 1.0f - 2.0f * (j + sy) / (float)params->height;
    float3 through = u * params->right.xyz + v * params->up.xyz + params->forward.xyz; /* at depth 1 */
    Ray ray = {params->eye.xyz, normalize(through), time};
    float lensRadius = params->lensRadius;
    if (lensRadius > 0.0f && !(params->features & RAY_FEATURE_LENS_DISK)) {
        float3 focus = ray.origin + params->focalDistance * through;
        ray.origin += lensRadius * lens.x * normalize(params->right.xyz) + lensRadius * lens.y * normalize(params->up.xyz);
        ray.direction = normalize(focus - ray.origin);
    } else if (lensRadius > 0.0f) {
        float3 focus = ray.origin + params->focalDistance * ray.direction;
        float r = lensRadius * sqrt(lens.x), phi = 2.0f * M_PI_F * lens.y;
        ray.origin += r * cos(phi) * normalize(params->right.xyz) + r * sin(phi) * normalize(params->up.xyz);
        ray.direction = normalize(focus - ray.origin);
    }
    return ray;
}

/* A sample's lens: the course's grid (SPEC §3) or one random point of the disk (--dof
 * disk), and how many lens rays it takes (RAY_LENS_GRID_SIDE² on the grid, else 1). */
static inline bool courseLensGrid(const RayRenderParams* params) {
    return params->lensRadius > 0.0f && !(params->features & RAY_FEATURE_LENS_DISK);
}

static inline int lensRaysPerSample(const RayRenderParams* params) {
    return courseLensGrid(params) ? RAY_LENS_GRID_SIDE * RAY_LENS_GRID_SIDE : 1;
}

/* Starts the pixel's next sample: numbers it, draws its shutter time from random dimension
 * 4 (shutter, params->shutter, 0 when nothing moves, times that number) and, with --dof
 * disk, its lens point from dimensions 2 and 3 (0 and 1 are the stratified jitter). */
static inline float2 startSample(const RayRenderParams* params, PixelTrace* counter) {
    uint k = counter->nextSample++;
    counter->sample = k;
    uint seed = (uint)params->seed;
    float2 lens = (float2)(0.0f);
    if (params->lensRadius > 0.0f && !courseLensGrid(params))
        lens = (float2)(rayRandom(counter->pixel, k, 2u, seed), rayRandom(counter->pixel, k, 3u, seed));
    float shutter = params->shutter;
    counter->time = shutter > 0.0f ? shutter * rayRandom(counter->pixel, k, 4u, seed) : 0.0f;
    return lens;
}

/* Lens ray l of a sample whose lens point is `lens` (startSample): on the course's grid,
 * grid point l. */
static inline float2 lensPoint(const RayRenderParams* params, int l, float2 lens) {
    if (!courseLensGrid(params)) return lens;
    return (float2)((float)(l % RAY_LENS_GRID_SIDE - RAY_LENS_GRID_SIDE / 2),
                    (float)(l / RAY_LENS_GRID_SIDE - RAY_LENS_GRID_SIDE / 2));
}

/* A lens ray's color as the sample sums it: clamped on the course's grid, whose mean of
 * clamped colors is the sample. */
static inline float3 lensRayTerm(const RayRenderParams* params, float3 color) {
    return courseLensGrid(params) ? clamp(color, 0.0f, 1.0f) : color;
}

