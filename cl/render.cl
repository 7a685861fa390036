/* The kernel: one work-item per pixel. A pixel's samples (SPEC §3) each trace a tree of
 * rays (a reflected and a refracted branch per hit) with an explicit stack, since
 * OpenCL C has no recursion. */

#ifndef RAY_MAX_FRAMES
#define RAY_MAX_FRAMES 5 /* max depth + 1; the host passes -DRAY_MAX_FRAMES */
#endif

/* A ray a hit spawns: its weight in its parent's color and the media it travels through
 * (cl/optics.cl). Its time is the camera sample's, given as it is traced. */
typedef struct {
    float3 origin, direction;
    float3 weight; /* ks·Or or kt·Ot (times R or 1 − R with --fresnel) */
    MediumStack media;
} ChildRay;

/* One ray of the tree awaiting its children. Its color is folded into its parent, clamped
 * to [0, 1] and weighted, once all of its children are folded into it (SPEC §4: I_r is
 * clamped before it is weighted). Its first child is traced as soon as it is spawned, so a
 * frame keeps only the second: private memory is what a GPU has least of. */
typedef struct {
    float3 color;          /* local shading plus the children folded in so far */
    float3 weightInParent; /* ks·Or (or kt·Ot) of the parent for this ray */
    ChildRay second;       /* the second child, traced once the first's tree is folded in */
    MediumStack media;     /* the media this frame's ray travels through */
    int childCount, nextChild, depth;
} Frame;

/* Where a frame's next spawned child goes: the first to `first`, which traceCameraRay
 * pushes at once, the second into the frame. */
static inline ChildRay* spawnedChild(Frame* frame, ChildRay* first) {
    return frame->childCount++ == 0 ? first : &frame->second;
}

static inline bool anyAbove(float3 v, float threshold) {
    return v.x >= threshold || v.y >= threshold || v.z >= threshold;
}

/* The kt·Ot branch (SPEC §4): the ray refracted by Snell's law into the medium beyond the
 * surface, or, under total internal reflection, the mirrored ray, which stays in the
 * medium it came from. normal (the shading normal) and surfaceNormal (the surface's own,
 * before a bump map tilts it) face the incoming direction d. */
void addRefractedChild(Frame* frame, ChildRay* first, float3 d, float3 p, float3 normal, float3 surfaceNormal,
                       bool entering, float materialIor, float3 weight, float epsilon) {
    MediumStack beyond;
    float n1 = iorBefore(&frame->media, entering, materialIor);
    float n2 = iorBeyond(&frame->media, entering, materialIor, &beyond);
    float3 transmitted;
    ChildRay* child = spawnedChild(frame, first);
    if (refractDirection(d, normal, n1, n2, &transmitted)) {
        child->direction = transmitted;
        child->origin = offsetAlongRay(p, -surfaceNormal, transmitted, epsilon); /* start on the far side */
        child->media = beyond;
    } else {
        child->direction = d - 2.0f * dot(d, normal) * normal;
        child->origin = offsetAlongRay(p, surfaceNormal, child->direction, epsilon);
        child->media = frame->media;
    }
    child->weight = weight;
}

/* The mirrored ray (I_r), which stays in the medium it came from (traceCameraRay sets its time). */
void addReflectedChild(Frame* frame, ChildRay* first, float3 d, float3 p, float3 normal, float3 surfaceNormal,
                       float3 weight, float epsilon) {
    ChildRay* child = spawnedChild(frame, first);
    child->direction = d - 2.0f * dot(d, normal) * normal;
    child->origin = offsetAlongRay(p, surfaceNormal, child->direction, epsilon);
    child->weight = weight;
    child->media = frame->media;
}

/* Whether a branch of weight `weight` below a frame whose path weight (the product of the
 * weights from the camera ray to it: pathWeightOf) is `pathWeight` is traced: --threshold
 * cuts it when its path weight is below the threshold in every channel, and a zero weight
 * is no branch. */
static inline bool branchTraced(const RayRenderParams* params, float3 pathWeight, float3 weight) {
    return anyAbove(pathWeight * weight, params->limits.x) && anyAbove(weight, 1e-30f);
}

/* The surfaces refraction applies to (SPEC §4): those of transparent objects (Ot != 0). */
static inline bool refracts(int features, float3 transparent) {
    return (features & RAY_FEATURE_REFRACTION) && anyAbove(fabs(transparent), 1e-30f);
}

/* --fresnel (SPEC §4): R, the exact Fresnel reflectance where the frame's ray meets a
 * transparent surface, from the medium it is in into the one beyond (cl/optics.cl). */
static inline float surfaceReflectance(const Frame* frame, float3 d, float3 normal, bool entering, float materialIor) {
    MediumStack beyond;
    float n1 = iorBefore(&frame->media, entering, materialIor);
    float n2 = iorBeyond(&frame->media, entering, materialIor, &beyond);
    return fresnelReflectance(-dot(d, normal), n1, n2);
}

/* A transparent object's surface met from inside (SPEC §4) adds nothing of its own:
 * I = clamp(I_t) with weight 1, so that kt·Ot applies once per object, on entry. With
 * --fresnel the light splits there as well, and the reflected part is kept inside the
 * object: I = R·clamp(I_r) + (1 − R)·clamp(I_t), I_r along the mirrored ray, which stays
 * inside (R = 1 under total internal reflection: the mirrored ray alone, as without
 * --fresnel). Both branches belong to refraction (--no-reflections keeps them) and
 * --threshold cuts each by its own weight, R or 1 − R times the path weight. */
static inline bool leavesTransparentObject(int features, bool entering, float3 transparent) {
    return !entering && refracts(features, transparent);
}

void transmitFromInside(const RayRenderParams* params, Frame* frame, float3 pathWeight, ChildRay* first, float3 d,
                        float3 p, float3 normal, float3 surfaceNormal, float materialIor) {
    if (frame->depth >= params->mode.y) return; /* no bounce left: I_t is black */
    if (!(params->mode.z & RAY_FEATURE_FRESNEL)) {
        addRefractedChild(frame, first, d, p, normal, surfaceNormal, false, materialIor, (float3)(1.0f),
                          params->limits.y);
        return;
    }
    float r = surfaceReflectance(frame, d, normal, false, materialIor);
    float3 reflectWeight = (float3)(r), transmitWeight = (float3)(1.0f - r);
    if (branchTraced(params, pathWeight, reflectWeight))
        addReflectedChild(frame, first, d, p, normal, surfaceNormal, reflectWeight, params->limits.y);
    if (branchTraced(params, pathWeight, transmitWeight))
        addRefractedChild(frame, first, d, p, normal, surfaceNormal, false, materialIor, transmitWeight,
                          params->limits.y);
}

/* Shades the hit of frame's ray: its color without the lights (which *lights starts to
 * sum) and the rays it spawns (the first in *first). False when it has no lights to sum (a
 * ray leaving a transparent object). */
static inline bool shadeHit(const SceneBuffers* scene, const RayRenderParams* params, Frame* frame, float3 pathWeight,
                            Ray ray, Hit hit, ChildRay* first, LightSamples* lights) {
    const bool courseMeshes = (params->mode.z & RAY_FEATURE_COURSE_MESHES) != 0;
    __global const RayPrimitive* prim = &scene->primitives[hit.primitive];
    RayMaterial m = scene->materials[prim->info.y];
    float3 p = ray.origin + hit.t * ray.direction;
    float3 faceNormal = hit.objectNormal; /* a mesh's: the triangle's, before its shading normal */
    /* --course-meshes: a mesh keeps its face normal */
    if (prim->info.x == RAY_PRIM_MESH && !courseMeshes)
        hit.objectNormal = meshShadingNormal(scene->triangleShading, hit.part, hit.barycentric);
    float2 uv = hitUv(scene, prim->info.x, &hit);
    float3 normal = normalToWorld(prim->worldToObject, hit.objectNormal);
    /* The object normal points outward. Which side the ray meets is the surface's own: a
     * bump map tilts the shading normal, not the surface (host/reference/reference_renderer.cpp). */
    bool entering = dot(normal, ray.direction) < 0.0f;
    float3 surfaceNormal = entering ? normal : -normal; /* facing the ray, before a bump map tilts it */
    if ((params->mode.z & RAY_FEATURE_TEXTURES) && m.maps.y >= 0) { /* bump maps follow the textures switch */
        hit.objectNormal = bumpedObjectNormal(
            scene, m.maps.y, uv, m.repeats.zw, objectTangent(scene, prim->info.x, hit.part, hit.objectPoint),
            bitangentSign(scene, prim->info.x, hit.part, faceNormal, hit.objectNormal), hit.objectNormal);
        normal = normalToWorld(prim->worldToObject, hit.objectNormal);
    }
    if (!entering) normal = -normal; /* face the incoming ray */
    float4 k = params->globals;                               /* ka, kd, ks, kt */
    int features = params->mode.z;
    if (leavesTransparentObject(features, entering, m.transparent.xyz)) {
        transmitFromInside(params, frame, pathWeight, first, ray.direction, p, normal, surfaceNormal, m.specular.w);
        return false;
    }

    float3 diffuse = k.y * m.diffuse.xyz;
    if ((features & RAY_FEATURE_TEXTURES) && m.maps.x >= 0) {
        float3 t = (features & RAY_FEATURE_TRILINEAR)
                       ? sampleTrilinear(scene, m.maps.x, uv, m.repeats.xy,
                                         textureFootprint(scene, params, prim, hit.part, hit.t, ray.direction, normal))
                   : (features & RAY_FEATURE_COURSE_FILTER)
                       ? sampleCourseBilinear(scene, m.maps.x, uv, m.repeats.xy)
                       : sampleTexture(scene, m.maps.x, uv, m.repeats.xy, (features & RAY_FEATURE_BILINEAR) != 0);
        float blend = m.diffuse.w;
        diffuse = blend * t + (1.0f - blend) * diffuse; /* the texture term is not scaled by kd */
    }
    frame->color = k.x * m.ambient.xyz + m.emissive.xyz; /* shadeFrame adds the lights */
    startLights(lights, p, normal, -ray.direction, diffuse, k.z * m.specular.xyz, m.ambient.w);

    if (frame->depth >= params->mode.y) return true;
    float3 reflectWeight = k.z * m.reflective.xyz;
    float3 transmitWeight = k.w * m.transparent.xyz;
    if ((features & RAY_FEATURE_FRESNEL) && refracts(features, m.transparent.xyz)) {
        /* ks·Or·R·I_r + kt·Ot·(1 − R)·I_t; under total internal reflection (R = 1) the
         * transmitted branch has weight 0 and is not traced. */
        float r = surfaceReflectance(frame, ray.direction, normal, entering, m.specular.w);
        reflectWeight *= r;
        transmitWeight *= 1.0f - r;
    }
    if ((features & RAY_FEATURE_REFLECTIONS) && branchTraced(params, pathWeight, reflectWeight))
        addReflectedChild(frame, first, ray.direction, p, normal, surfaceNormal, reflectWeight, params->limits.y);
    if ((features & RAY_FEATURE_REFRACTION) && branchTraced(params, pathWeight, transmitWeight))
        addRefractedChild(frame, first, ray.direction, p, normal, surfaceNormal, entering, m.specular.w, transmitWeight,
                          params->limits.y);
    return true;
}

/* Traces frame's ray, shades the hit and records the rays it spawns (the first in *first).
 * One traceBvh call traces the frame's ray (closest hit) and then the shadow ray of each
 * light sample (any hit; LightSamples): a GPU compiler inlines every call site, the whole
 * BVH walk with every intersector, and a second site inside the light loop, with all of
 * the shading values live around it, grew the code by a third and the private memory a
 * work-item by an eighth (docs/performance.md). The hit's children are spawned
 * before its lights are summed, so that only the walk over the lights is live around the
 * shadow rays' trace. */
void shadeFrame(const SceneBuffers* scene, const RayRenderParams* params, Frame* frame, float3 pathWeight, Ray ray,
                ChildRay* first, PixelTrace* counter) {
    frame->color = (float3)(0.0f);
    frame->childCount = 0;
    frame->nextChild = 0;
    const bool courseMeshes = (params->mode.z & RAY_FEATURE_COURSE_MESHES) != 0;
    LightSamples lights;
    bool shadowRay = false; /* ray: a light sample's shadow ray, or else the frame's ray */
    float tMax = RAY_INFINITY;
    while (true) {
        Hit hit;
        bool found = traceBvh(scene->nodes, scene->primitives, scene->triangles, scene->motions, ray, tMax, shadowRay,
                              courseMeshes && !shadowRay, &hit);
        if (shadowRay) {
            if (!found) addUnblockedSample(&lights);
        } else if (!found || !shadeHit(scene, params, frame, pathWeight, ray, hit, first, &lights)) {
            return; /* nothing hit, or no lights to sum */
        }
        if (!nextShadowRay(&lights, scene, params, counter, &ray, &tMax)) break;
        shadowRay = true;
    }
    frame->color += lights.sum;
}

/* The path weight of frame `top`: the product of the weights from the camera ray to it,
 * multiplied in the order the tree spawned them, so that it is the same to the bit as a
 * product kept in each frame; recomputed, because private memory is what a GPU has least of. */
static inline float3 pathWeightOf(const Frame* stack, int top) {
    float3 weight = (float3)(1.0f);
    for (int k = 1; k <= top; ++k) weight *= stack[k].weightInParent;
    return weight;
}

/* The color of one camera ray: the tree of reflected rays below it, depth first. Each ray
 * of the tree is shaded at the one shadeFrame call below (which traces it and its shadow
 * rays at one traceBvh call), the loop's first step whenever a frame has just been pushed
 * (a GPU compiler inlines every call site). */
float3 traceCameraRay(const SceneBuffers* scene, const RayRenderParams* params, Ray ray, PixelTrace* counter) {
    Frame stack[RAY_MAX_FRAMES];
    int top = 0;
    stack[0].depth = 0;
    stack[0].weightInParent = (float3)(1.0f);
    stack[0].media.count = 0; /* the camera is in air */
    counter->primary++;
    bool pushed = true; /* stack[top] awaits shading along `ray` */
    ChildRay first;     /* the first child of the frame shaded last */
    while (true) {
        Frame* frame = &stack[top];
        if (pushed) {
            shadeFrame(scene, params, frame, pathWeightOf(stack, top), ray, &first, counter);
            pushed = false;
        }
        if (frame->nextChild < frame->childCount && top + 1 < RAY_MAX_FRAMES) {
            const ChildRay* spawned = frame->nextChild++ == 0 ? &first : &frame->second;
            Frame* child = &stack[top + 1];
            child->depth = frame->depth + 1;
            child->weightInParent = spawned->weight;
            child->media = spawned->media;
            counter->secondary++;
            ray.origin = spawned->origin; /* ray.time stays: every ray of the tree sees the */
            ray.direction = spawned->direction; /* scene at its camera sample's time */
            ++top;
            pushed = true;
            continue;
        }
        if (top == 0) return frame->color;
        float3 folded = frame->weightInParent * clamp(frame->color, 0.0f, 1.0f);
        --top;
        stack[top].color += folded;
    }
}

/* The camera ray through offset (sx, sy) of pixel (i, j) (SPEC §3). With depth of field
 * the eye moves to a point of the lens in the plane of U and V. The course's lens (SPEC §3):
 * lens = grid point (i, j) ∈ {−2..2}², the eye moving by i·a/2 along U and j·a/2 along V
 * (a/2 = the lens radius), the ray aimed where the pinhole ray meets the plane at depth
 * focallength along the look axis. --dof disk: a point of the lens disk picked by lens ∈
 * [0, 1)², the ray aimed at the point the pinhole ray reaches at the focal distance. */
static inline Ray cameraRay(const RayRenderParams* params, float i, float j, float sx, float sy, float2 lens, float time) {
    float u = 2.0f * (i + sx) / (float)params->image.x - 1.0f;
    float v = 1.0f - 2.0f * (j + sy) / (float)params->image.y;
    float3 through = u * params->right.xyz + v * params->up.xyz + params->forward.xyz; /* at depth 1 */
    Ray ray = {params->eye.xyz, normalize(through), time};
    float lensRadius = params->lens.x;
    if (lensRadius > 0.0f && !(params->mode.z & RAY_FEATURE_LENS_DISK)) {
        float3 focus = ray.origin + params->lens.y * through;
        ray.origin += lensRadius * lens.x * normalize(params->right.xyz) + lensRadius * lens.y * normalize(params->up.xyz);
        ray.direction = normalize(focus - ray.origin);
    } else if (lensRadius > 0.0f) {
        float3 focus = ray.origin + params->lens.y * ray.direction;
        float r = lensRadius * sqrt(lens.x), phi = 2.0f * M_PI_F * lens.y;
        ray.origin += r * cos(phi) * normalize(params->right.xyz) + r * sin(phi) * normalize(params->up.xyz);
        ray.direction = normalize(focus - ray.origin);
    }
    return ray;
}

/* One sample of the pixel, unclamped; its shutter time from random dimension 4: shutter
 * (params->lens.z, 0 when nothing moves) times that number. With the course's lens (SPEC §3)
 * the sample is the mean of the RAY_LENS_GRID_SIDE² lens rays' clamped colors, one trace
 * site in a loop; --dof disk draws one lens point from dimensions 2 and 3 of the sample's
 * number (0 and 1 are the stratified jitter). */
static inline float3 traceSample(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, float sx, float sy,
                          PixelTrace* counter) {
    uint k = counter->nextSample++;
    counter->sample = k;
    uint seed = (uint)params->counts.w;
    const bool lensGrid = params->lens.x > 0.0f && !(params->mode.z & RAY_FEATURE_LENS_DISK);
    float2 lens = (float2)(0.0f);
    if (params->lens.x > 0.0f && !lensGrid)
        lens = (float2)(rayRandom(counter->pixel, k, 2u, seed), rayRandom(counter->pixel, k, 3u, seed));
    float shutter = params->lens.z;
    counter->time = shutter > 0.0f ? shutter * rayRandom(counter->pixel, k, 4u, seed) : 0.0f;
    const int lensRays = lensGrid ? RAY_LENS_GRID_SIDE * RAY_LENS_GRID_SIDE : 1;
    float3 sum = (float3)(0.0f);
    for (int l = 0; l < lensRays; ++l) {
        if (lensGrid)
            lens = (float2)((float)(l % RAY_LENS_GRID_SIDE - RAY_LENS_GRID_SIDE / 2),
                            (float)(l / RAY_LENS_GRID_SIDE - RAY_LENS_GRID_SIDE / 2));
        float3 color = traceCameraRay(scene, params, cameraRay(params, (float)i, (float)j, sx, sy, lens, counter->time),
                                      counter);
        sum += lensGrid ? clamp(color, 0.0f, 1.0f) : color;
    }
    return sum / (float)lensRays;
}

static inline float largestChannel(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

/* Whether two samples differ by more than RAY_COURSE_AA_CONTRAST in some channel. */
static inline bool courseDiffers(float3 a, float3 b) {
    return largestChannel(fabs(a - b)) > RAY_COURSE_AA_CONTRAST;
}

/* Which quadrants of a, b, c, d the course subdivides: bit 0 a, 1 b, 2 c, 3 d. */
static inline int courseSubdivided(float3 a, float3 b, float3 c, float3 d) {
    int bits = 0;
    if (courseDiffers(a, b)) bits |= 1 | 2;
    if (courseDiffers(c, d)) bits |= 4 | 8;
    if (courseDiffers(a, c)) bits |= 1 | 4;
    if (courseDiffers(b, d)) bits |= 2 | 8;
    return bits;
}

/* Every antialiasing mode as a state machine that hands out one sample position at a time
 * and takes that sample's color back, so that the whole pixel is one loop around one
 * traceSample call (renderTile). A GPU compiler inlines every call: written as recursion-
 * free nested functions, the course's three levels alone held 84 copies of the trace.
 *
 * The course's adaptive antialiasing (docs/conventions.md, "Antialiasing";
 * host/reference/course_sampling.cpp): value(square, level) samples the centres of the
 * square's four quadrants a (top left), b (top right), c (bottom left), d (bottom right);
 * where level < 3, a quadrant whose sample differs from a horizontal or vertical
 * neighbour's (a–b, c–d, a–c, b–d; not the diagonals) by more than RAY_COURSE_AA_CONTRAST
 * in some channel is replaced by value(quadrant, level + 1). The result is the mean of the
 * four. The machine walks that recursion depth first with an explicit stack of levels, so
 * samples are taken (and numbered) in the order the recursive form takes them.
 *
 * --aa stratified: an n×n grid (n = floor(sqrt(samples))), one jittered sample per cell
 * warped through the tent reconstruction filter (rayTentOffset), averaged.
 * --aa adaptive (host/reference/course_sampling.h sampleAdaptive): 2×2 jittered samples
 * (numbers 0..3); where they spread by more than RAY_ADAPTIVE_CONTRAST, a k×k jittered grid
 * more (numbers 4..); the mean of every sample taken. With samples <= 4, stratified.
 * --aa off: one unclamped sample at the pixel's centre (for float outputs). */
#define RAY_COURSE_LEVELS 3

typedef struct {
    /* the course's machine, one entry per level of its recursion */
    float3 quadrant[RAY_COURSE_LEVELS][4]; /* the (clamped) values of a, b, c, d */
    float2 corner[RAY_COURSE_LEVELS];      /* the top left corner of the level's square */
    int taken[RAY_COURSE_LEVELS];          /* samples taken at the level: 0..4, then 5 once judged */
    int toRefine[RAY_COURSE_LEVELS];       /* quadrants still to replace by the next level */
    int refining[RAY_COURSE_LEVELS];       /* the quadrant the next level replaces */
    int level;                             /* the level being sampled; -1 when the pixel is done */
    /* the jittered modes */
    float3 sum, low, high; /* of the samples taken; low and high of the first four (adaptive) */
    int count, side;       /* samples taken; the side of the grid being sampled */
    int extra;             /* adaptive: whether the k×k grid is being taken */
    float3 result;
} PixelSampler;

static inline void startSampler(PixelSampler* s, const RayRenderParams* params) {
    s->level = 0;
    s->corner[0] = (float2)(0.0f);
    s->taken[0] = 0;
    s->sum = (float3)(0.0f);
    s->low = (float3)(INFINITY);
    s->high = (float3)(-INFINITY);
    s->count = 0;
    s->extra = 0;
    int samples = params->mode.w;
    bool stratified = params->mode.x == RAY_AA_STRATIFIED || samples <= 4;
    s->side = stratified ? max(1, (int)floor(sqrt((float)samples))) : 2;
    s->result = (float3)(0.0f);
}

/* The course's machine: the next sample position, or false when the pixel's value is
 * known (s->result). A level whose four samples are in is judged once; its quadrants to
 * refine are then entered one by one, and a finished level hands its mean to its parent. */
static inline bool nextCoursePosition(PixelSampler* s, float2* position) {
    while (s->level >= 0) {
        int l = s->level;
        float size = 1.0f / (float)(1 << l);
        if (s->taken[l] < 4) {
            int q = s->taken[l];
            float quarter = size * 0.25f;
            *position = s->corner[l] + (float2)((q & 1) ? 3.0f * quarter : quarter, (q & 2) ? 3.0f * quarter : quarter);
            return true;
        }
        if (s->taken[l] == 4) { /* judged once, before any quadrant is replaced */
            s->toRefine[l] = l + 1 < RAY_COURSE_LEVELS ? courseSubdivided(s->quadrant[l][0], s->quadrant[l][1],
                                                                          s->quadrant[l][2], s->quadrant[l][3])
                                                       : 0;
            s->taken[l] = 5;
        }
        if (s->toRefine[l] != 0) {
            int q = 0;
            while (!(s->toRefine[l] & (1 << q))) ++q; /* a, b, c, d in turn */
            s->toRefine[l] &= ~(1 << q);
            s->refining[l] = q;
            float halfSize = size * 0.5f;
            s->corner[l + 1] = s->corner[l] + (float2)((q & 1) ? halfSize : 0.0f, (q & 2) ? halfSize : 0.0f);
            s->taken[l + 1] = 0;
            s->level = l + 1;
            continue;
        }
        float3 mean = 0.25f * (s->quadrant[l][0] + s->quadrant[l][1] + s->quadrant[l][2] + s->quadrant[l][3]);
        s->level = l - 1;
        if (l == 0) s->result = mean;
        else s->quadrant[l - 1][s->refining[l - 1]] = mean;
    }
    return false;
}

/* The jittered modes: sample number s->count (its random numbers pick the jitter) in cell
 * `cell` of the side×side grid being sampled. */
static inline bool nextJitteredPosition(PixelSampler* s, const RayRenderParams* params, uint pixel, float2* position) {
    int cell = s->extra ? s->count - 4 : s->count;
    if (cell >= s->side * s->side) {
        bool refine = params->mode.x == RAY_AA_ADAPTIVE && params->mode.w > 4 && !s->extra &&
                      largestChannel(s->high - s->low) > RAY_ADAPTIVE_CONTRAST;
        if (!refine) {
            s->result = s->sum / (float)s->count;
            return false;
        }
        s->extra = 1;
        s->side = max(1, (int)floor(sqrt((float)params->mode.w)));
        cell = 0;
    }
    uint seed = (uint)params->counts.w, number = (uint)s->count;
    float side = (float)s->side;
    *position = (float2)(rayTentOffset(((float)(cell % s->side) + rayRandom(pixel, number, 0u, seed)) / side),
                         rayTentOffset(((float)(cell / s->side) + rayRandom(pixel, number, 1u, seed)) / side));
    return true;
}

/* The position of the pixel's next sample, in [0, 1)², or false when the pixel is done
 * and its color is in s->result. */
static inline bool nextSamplePosition(PixelSampler* s, const RayRenderParams* params, uint pixel, float2* position) {
    switch (params->mode.x) {
        case RAY_AA_COURSE: return nextCoursePosition(s, position);
        case RAY_AA_STRATIFIED:
        case RAY_AA_ADAPTIVE: return nextJitteredPosition(s, params, pixel, position);
        default:
            if (s->count > 0) return false;
            *position = (float2)(0.5f);
            return true;
    }
}

/* Takes the color of the sample at the position nextSamplePosition gave: clamped, except
 * with --aa off, whose one sample is the pixel's unclamped color. */
static inline void addSample(PixelSampler* s, const RayRenderParams* params, float3 color) {
    if (params->mode.x == RAY_AA_OFF) {
        s->result = color;
        s->count++;
        return;
    }
    color = clamp(color, 0.0f, 1.0f);
    if (params->mode.x == RAY_AA_COURSE) {
        int l = s->level;
        s->quadrant[l][s->taken[l]++] = color;
        return;
    }
    s->sum += color;
    if (s->count < 4) {
        s->low = fmin(s->low, color);
        s->high = fmax(s->high, color);
    }
    s->count++;
}

/* The color of pixel (i, j): every sample the antialiasing mode asks for, traced at the one
 * trace site. A call on PoCL: there the work-group function runs the kernel for each
 * work-item in a loop and keeps the private variables of the kernel's own body in arrays
 * with an entry per work-item (the sampler, the ray tree's frames), whose addressing cost
 * chess 3% more instructions than a call with its own stack frame. */
static RAY_CALL_ON_POCL float3 renderPixel(const SceneBuffers* scene, const RayRenderParams* params, int i, int j,
                                           PixelTrace* counter) {
    PixelSampler sampler;
    startSampler(&sampler, params);
    float2 position;
    while (nextSamplePosition(&sampler, params, counter->pixel, &position)) {
        float3 color = traceSample(scene, params, i, j, position.x, position.y, counter); /* the one trace site */
        addSample(&sampler, params, color);
    }
    return sampler.result;
}

/* On AMD GCN, at least 4 waves a SIMD: the register budget (64 VGPRs) that keeps enough
 * work-items in flight to hide memory latency. What does not fit spills to scratch, which
 * scripts/kernel_resources.py counts in the kernel's private memory. */
#if defined(__AMDGCN__)
#define RAY_KERNEL_OCCUPANCY __attribute__((amdgpu_waves_per_eu(4)))
#else
#define RAY_KERNEL_OCCUPANCY
#endif

/* Renders one tile: work-item (x, y) is pixel (tile x0 + x, tile y0 + y) of the image and
 * element y * tile width + x of the tile outputs. Its arguments: the launch parameters, the
 * scene's buffers in the order of their list (cl/shared_types.h RAY_SCENE_BUFFERS), then the
 * tile's outputs; the host numbers them so (host/opencl/kernel_arguments.h). */
#define RAY_SCENE_BUFFER_PARAMETER(Type, name, what) __global const Type* name,
#define RAY_SCENE_BUFFER_NAME(Type, name, what) name,
__kernel RAY_KERNEL_OCCUPANCY void renderTile(RayRenderParams params, RAY_SCENE_BUFFERS(RAY_SCENE_BUFFER_PARAMETER)
                                              __global float4* tileColors, __global uint4* tileRayCounts) {
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= params.tile.x || y >= params.tile.y) return;
    int i = params.image.z + x, j = params.image.w + y;
    if (i >= params.image.x || j >= params.image.y) return;

    SceneBuffers scene = {RAY_SCENE_BUFFERS(RAY_SCENE_BUFFER_NAME)};
    PixelTrace counter = {0u, 0u, 0u, (uint)(j * params.image.x + i), 0u, 0u, 0.0f};
    float3 color = renderPixel(&scene, &params, i, j, &counter);
    int pixel = y * params.tile.x + x; /* the outputs hold this tile alone, row by row */
    tileColors[pixel] = (float4)(color, 1.0f);
    tileRayCounts[pixel] = (uint4)(counter.primary, counter.shadow, counter.secondary, 0u);
}
#undef RAY_SCENE_BUFFER_PARAMETER
#undef RAY_SCENE_BUFFER_NAME
