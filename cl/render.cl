/* A pixel's samples (SPEC §3), each tracing a tree of rays (a reflected and a refracted
 * branch per hit) with an explicit stack, since OpenCL C has no recursion: renderPixel,
 * one pixel a work-item (GPUs), and the pieces the packet path of CPU devices shares
 * (cl/packet_render.cl). The entry point is cl/kernel.cl. */

#ifndef RAY_MAX_FRAMES
#define RAY_MAX_FRAMES 5 /* max depth + 1; the host passes -DRAY_MAX_FRAMES */
#endif

/* A float3 kept in 12 bytes: in a private struct a float3 takes 16, and private memory is
 * what a GPU has least of. Only loads and stores change: the arithmetic stays on float3. */
typedef struct {
    float x, y, z;
} PackedFloat3;

static inline PackedFloat3 packFloat3(float3 v) {
    PackedFloat3 packed = {v.x, v.y, v.z};
    return packed;
}

static inline float3 unpackFloat3(PackedFloat3 packed) { return (float3)(packed.x, packed.y, packed.z); }

/* How a child ray's media (cl/optics.cl) follow from its parent's: a reflected ray, or a
 * refracted one under total internal reflection, stays in its parent's; a refracted ray
 * enters the object (pushes its ior) or leaves it (pops). Kept instead of the media
 * themselves, which mediaOf rebuilds. */
#define RAY_MEDIUM_SAME 0
#define RAY_MEDIUM_ENTERED 1
#define RAY_MEDIUM_LEFT 2

/* A ray a hit spawns, kept until it is traced: its weight in its parent's color and its
 * medium change (the kind in its frame). Its time is the camera sample's, given as it is
 * traced. */
typedef struct {
    PackedFloat3 origin, direction;
    PackedFloat3 weight; /* ks·Or or kt·Ot (times R or 1 − R with --fresnel) */
    float enteredIor;    /* the ior it pushes when its medium change is RAY_MEDIUM_ENTERED */
} ChildRay;

/* One ray of the tree awaiting its children; its depth is its index in the stack. Its
 * color is folded into its parent, clamped to [0, 1] and weighted, once all of its
 * children are folded into it (SPEC §4: I_r is clamped before it is weighted). Its first
 * child is written straight into the frame above it and the ray traced next, and pushed at
 * once, so only the second is kept (RayTree): private memory is what a GPU has least of. */
typedef struct {
    PackedFloat3 color;          /* local shading plus the children folded in so far */
    PackedFloat3 weightInParent; /* ks·Or (or kt·Ot) of the parent for this ray */
    float enteredIor;            /* the ior this ray pushes if its medium is RAY_MEDIUM_ENTERED */
    uchar medium;                /* this ray's medium change from its parent's (RAY_MEDIUM_*) */
    uchar secondMedium;          /* the second child's */
    uchar childCount, nextChild; /* 0..2 */
} Frame;

/* The ray tree's stack: the frames, and the second child of each frame that can spawn
 * (every frame but the last), traced once the first's tree is folded in. */
typedef struct {
    Frame frames[RAY_MAX_FRAMES];
    ChildRay seconds[RAY_MAX_FRAMES > 1 ? RAY_MAX_FRAMES - 1 : 1];
} RayTree;

/* Whether a frame at `depth` spawns no child: the bounce limit (--depth), which the host
 * makes RAY_MAX_FRAMES − 1, so that the first child always has a frame above to go to. */
static inline bool atDepthLimit(const RayRenderParams* params, int depth) {
    return depth >= params->mode.y || depth + 1 >= RAY_MAX_FRAMES;
}

/* Records a ray spawned by `frame`: the first goes straight into the frame above (`above`)
 * and the ray traced next (`aboveRay`; its time stays: every ray of the tree sees the
 * scene at its camera sample's time), the second into the frame. */
static inline void spawnChild(RayTree* tree, int depth, Ray* aboveRay, float3 origin, float3 direction,
                              float3 weight, uchar medium, float enteredIor) {
    Frame* frame = &tree->frames[depth];
    if (frame->childCount++ == 0) {
        Frame* above = &tree->frames[depth + 1]; /* in the stack: atDepthLimit */
        aboveRay->origin = origin;
        aboveRay->direction = direction;
        above->weightInParent = packFloat3(weight);
        above->medium = medium;
        above->enteredIor = enteredIor;
        return;
    }
    ChildRay* second = &tree->seconds[depth];
    second->origin = packFloat3(origin);
    second->direction = packFloat3(direction);
    second->weight = packFloat3(weight);
    second->enteredIor = enteredIor;
    frame->secondMedium = medium;
}

/* The path weight of frame `top`: the product of the weights from the camera ray to it,
 * multiplied in the order the tree spawned them, so that it is the same to the bit as a
 * product kept in each frame; recomputed, because private memory is what a GPU has least of. */
static inline float3 pathWeightOf(const Frame* stack, int top) {
    float3 weight = (float3)(1.0f);
    for (int k = 1; k <= top; ++k) weight *= unpackFloat3(stack[k].weightInParent);
    return weight;
}

/* The media of frame `top`'s ray: the camera's (air) changed by each frame's medium change
 * from the camera ray up, as iorBeyond changed them when the frames were spawned. Rebuilt
 * where a transparent surface needs them, because private memory is what a GPU has least
 * of (and most rays never meet one). */
static inline MediumStack mediaOf(const Frame* stack, int top) {
    MediumStack media;
    media.count = 0; /* the camera is in air */
    for (int k = 1; k <= top; ++k) {
        if (stack[k].medium == RAY_MEDIUM_SAME) continue;
        MediumStack beyond;
        iorBeyond(&media, stack[k].medium == RAY_MEDIUM_ENTERED, stack[k].enteredIor, &beyond);
        media = beyond;
    }
    return media;
}

static inline bool anyAbove(float3 v, float threshold) {
    return v.x >= threshold || v.y >= threshold || v.z >= threshold;
}

/* The kt·Ot branch (SPEC §4): the ray refracted by Snell's law into the medium beyond the
 * surface, or, under total internal reflection, the mirrored ray, which stays in the
 * medium it came from. normal (the shading normal) and surfaceNormal (the surface's own,
 * before a bump map tilts it) face the incoming direction d. */
void addRefractedChild(RayTree* tree, int depth, Ray* aboveRay, float3 d, float3 p,
                       float3 normal, float3 surfaceNormal, bool entering, float materialIor, float3 weight,
                       float epsilon) {
    MediumStack media = mediaOf(tree->frames, depth), beyond;
    float n1 = iorBefore(&media, entering, materialIor);
    float n2 = iorBeyond(&media, entering, materialIor, &beyond);
    float3 transmitted;
    if (refractDirection(d, normal, n1, n2, &transmitted)) {
        spawnChild(tree, depth, aboveRay, offsetAlongRay(p, -surfaceNormal, transmitted, epsilon), /* far side */
                   transmitted, weight, entering ? RAY_MEDIUM_ENTERED : RAY_MEDIUM_LEFT, materialIor);
    } else {
        float3 mirrored = d - 2.0f * dot(d, normal) * normal;
        spawnChild(tree, depth, aboveRay, offsetAlongRay(p, surfaceNormal, mirrored, epsilon), mirrored, weight,
                   RAY_MEDIUM_SAME, 0.0f);
    }
}

/* The mirrored ray (I_r), which stays in the medium it came from. */
void addReflectedChild(RayTree* tree, int depth, Ray* aboveRay, float3 d, float3 p, float3 normal,
                       float3 surfaceNormal, float3 weight, float epsilon) {
    float3 mirrored = d - 2.0f * dot(d, normal) * normal;
    spawnChild(tree, depth, aboveRay, offsetAlongRay(p, surfaceNormal, mirrored, epsilon), mirrored, weight,
               RAY_MEDIUM_SAME, 0.0f);
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

/* --fresnel (SPEC §4): R, the exact Fresnel reflectance where the ray of frame
 * stack[depth] meets a transparent surface, from the medium it is in into the one beyond
 * (cl/optics.cl). */
static inline float surfaceReflectance(const Frame* stack, int depth, float3 d, float3 normal, bool entering,
                                       float materialIor) {
    MediumStack media = mediaOf(stack, depth), beyond;
    float n1 = iorBefore(&media, entering, materialIor);
    float n2 = iorBeyond(&media, entering, materialIor, &beyond);
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

RAY_INLINED_ON_GPU
void transmitFromInside(const RayRenderParams* params, RayTree* tree, int depth, Ray* aboveRay, float3 d,
                        float3 p, float3 normal, float3 surfaceNormal, float materialIor) {
    if (atDepthLimit(params, depth)) return; /* no bounce left: I_t is black */
    float3 pathWeight = pathWeightOf(tree->frames, depth);
    if (!(params->mode.z & RAY_FEATURE_FRESNEL)) {
        addRefractedChild(tree, depth, aboveRay, d, p, normal, surfaceNormal, false, materialIor,
                          (float3)(1.0f), params->limits.y);
        return;
    }
    float r = surfaceReflectance(tree->frames, depth, d, normal, false, materialIor);
    float3 reflectWeight = (float3)(r), transmitWeight = (float3)(1.0f - r);
    if (branchTraced(params, pathWeight, reflectWeight))
        addReflectedChild(tree, depth, aboveRay, d, p, normal, surfaceNormal, reflectWeight, params->limits.y);
    if (branchTraced(params, pathWeight, transmitWeight))
        addRefractedChild(tree, depth, aboveRay, d, p, normal, surfaceNormal, false, materialIor,
                          transmitWeight, params->limits.y);
}

/* Shades the hit of the ray of frame tree->frames[depth]: its color without the lights
 * (which *lights starts to sum) and the rays it spawns (spawnChild: the first into the
 * frame above and *next). False when it has no lights to sum (a ray leaving a transparent
 * object). */
static inline bool shadeHit(const SceneBuffers* scene, const RayRenderParams* params, RayTree* tree, int depth,
                            Ray ray, Hit hit, Ray* next, LightSamples* lights) {
    Frame* frame = &tree->frames[depth];
    const bool courseMeshes = (params->mode.z & RAY_FEATURE_COURSE_MESHES) != 0;
    __global const RayPrimitive* prim = &scene->primitives[hit.primitive];
    /* read where it lies: a private copy of the material (128 B) was loaded whole and held
     * across the shading, 48 B of gfx906 scratch */
    __global const RayMaterial* m = &scene->materials[prim->info.y];
    float3 p = ray.origin + hit.t * ray.direction;
    float3 faceNormal = hit.objectNormal; /* a mesh's: the triangle's, before its shading normal */
    /* --course-meshes: a mesh keeps its face normal */
    if (prim->info.x == RAY_PRIM_MESH && !courseMeshes)
        hit.objectNormal = meshShadingNormal(scene->triangleShading, hit.part, hit.barycentric);
    /* only a texture or a bump map reads uv: computed for every hit, the sphere's atan2 and
     * asin were 3% of PoCL's instructions on spheres_1e4 (202.9 -> 197.1 M), which has neither */
    const bool mapped = (params->mode.z & RAY_FEATURE_TEXTURES) && (m->maps.x >= 0 || m->maps.y >= 0);
    float2 uv = mapped ? hitUv(scene, prim->info.x, &hit) : (float2)(0.0f);
    float3 normal = normalToWorld(prim->worldToObject, hit.objectNormal);
    /* The object normal points outward. Which side the ray meets is the surface's own: a
     * bump map tilts the shading normal, not the surface (host/reference/reference_renderer.cpp). */
    bool entering = dot(normal, ray.direction) < 0.0f;
    float3 surfaceNormal = entering ? normal : -normal; /* facing the ray, before a bump map tilts it */
    if ((params->mode.z & RAY_FEATURE_TEXTURES) && m->maps.y >= 0) { /* bump maps follow the textures switch */
        hit.objectNormal = bumpedObjectNormal(
            scene, m->maps.y, uv, m->repeats.zw, objectTangent(scene, prim->info.x, hit.part, hit.objectPoint),
            bitangentSign(scene, prim->info.x, hit.part, faceNormal, hit.objectNormal), hit.objectNormal);
        normal = normalToWorld(prim->worldToObject, hit.objectNormal);
    }
    if (!entering) normal = -normal; /* face the incoming ray */
    float4 k = params->globals;                               /* ka, kd, ks, kt */
    int features = params->mode.z;
    if (leavesTransparentObject(features, entering, m->transparent.xyz)) {
        transmitFromInside(params, tree, depth, next, ray.direction, p, normal, surfaceNormal, m->specular.w);
        return false;
    }

    float3 diffuse = k.y * m->diffuse.xyz;
    if ((features & RAY_FEATURE_TEXTURES) && m->maps.x >= 0) {
        float3 t = (features & RAY_FEATURE_TRILINEAR)
                       ? sampleTrilinear(scene, m->maps.x, uv, m->repeats.xy,
                                         textureFootprint(scene, params, prim, hit.part, hit.t, ray.direction, normal))
                   : (features & RAY_FEATURE_COURSE_FILTER)
                       ? sampleCourseBilinear(scene, m->maps.x, uv, m->repeats.xy)
                       : sampleTexture(scene, m->maps.x, uv, m->repeats.xy, (features & RAY_FEATURE_BILINEAR) != 0);
        float blend = m->diffuse.w;
        diffuse = blend * t + (1.0f - blend) * diffuse; /* the texture term is not scaled by kd */
    }
    frame->color = packFloat3(k.x * m->ambient.xyz + m->emissive.xyz); /* shadeFrame adds the lights */
    startLights(lights, p, normal, -ray.direction, diffuse, k.z * m->specular.xyz, m->ambient.w,
                params->limits.y);

    if (atDepthLimit(params, depth)) return true;
    float3 pathWeight = pathWeightOf(tree->frames, depth);
    float3 reflectWeight = k.z * m->reflective.xyz;
    float3 transmitWeight = k.w * m->transparent.xyz;
    if ((features & RAY_FEATURE_FRESNEL) && refracts(features, m->transparent.xyz)) {
        /* ks·Or·R·I_r + kt·Ot·(1 − R)·I_t; under total internal reflection (R = 1) the
         * transmitted branch has weight 0 and is not traced. */
        float r = surfaceReflectance(tree->frames, depth, ray.direction, normal, entering, m->specular.w);
        reflectWeight *= r;
        transmitWeight *= 1.0f - r;
    }
    if ((features & RAY_FEATURE_REFLECTIONS) && branchTraced(params, pathWeight, reflectWeight))
        addReflectedChild(tree, depth, next, ray.direction, p, normal, surfaceNormal, reflectWeight,
                          params->limits.y);
    if ((features & RAY_FEATURE_REFRACTION) && branchTraced(params, pathWeight, transmitWeight))
        addRefractedChild(tree, depth, next, ray.direction, p, normal, surfaceNormal, entering,
                          m->specular.w, transmitWeight, params->limits.y);
    return true;
}

/* A frame about to be shaded: no color and no children yet. */
static inline void startFrame(Frame* frame) {
    frame->color = packFloat3((float3)(0.0f));
    frame->childCount = 0;
    frame->nextChild = 0;
}

/* Adds a shaded frame's direct lighting, summed (LightSamples), to its color. */
static inline void addLights(Frame* frame, const LightSamples* lights) {
    frame->color = packFloat3(unpackFloat3(frame->color) + lights->sum);
}

/* Traces the ray of frame tree->frames[depth], shades the hit and records the rays it
 * spawns (spawnChild: the first into the frame above and *next). One traceBvh call traces
 * the frame's ray (closest hit) and then the shadow ray of each light sample (any hit;
 * LightSamples): a GPU compiler inlines every call site, the whole BVH walk with every
 * intersector, and a second site inside the light loop, with all of the shading values
 * live around it, grew the code by a third and the private memory a work-item by an
 * eighth (docs/performance.md). The hit's children are spawned before its lights are
 * summed, so that only the walk over the lights is live around the shadow rays' trace.
 *
 * frameRay is copied before anything is written: traceCameraRay passes its own ray by value
 * and as *next, and Mesa's rusticl hands a struct argument over by reference (a by-value
 * parameter written in place wrote the caller's ray: the first child, written to *next, came
 * back as the last shadow ray, and tests/rusticl.sh saw mirrors differ from PoCL's). */
RAY_INLINED_ON_GPU
void shadeFrame(const SceneBuffers* scene, const RayRenderParams* params, RayTree* tree, int depth, Ray frameRay,
                Ray* next, PixelTrace* counter) {
    Frame* frame = &tree->frames[depth];
    startFrame(frame);
    const bool courseMeshes = (params->mode.z & RAY_FEATURE_COURSE_MESHES) != 0;
    LightSamples lights;
    bool shadowRay = false; /* ray: a light sample's shadow ray, or else the frame's ray */
    float tMax = RAY_INFINITY;
    Ray ray = frameRay; /* then each light sample's shadow ray */
    while (true) {
        Hit hit;
        bool found = traceBvh(scene->nodes, scene->cpuNodes, scene->primitives, scene->triangles, scene->motions, ray,
                              tMax, shadowRay, courseMeshes && !shadowRay, &hit);
        if (shadowRay) {
            if (!found) addUnblockedSample(&lights);
        } else if (!found || !shadeHit(scene, params, tree, depth, ray, hit, next, &lights)) {
            return; /* nothing hit, or no lights to sum */
        }
        if (!nextShadowRay(&lights, scene, params, counter, &ray, &tMax)) break;
        shadowRay = true;
    }
    addLights(frame, &lights);
}

/* The color of one camera ray's tree of reflected and refracted rays, depth first, from
 * `ray`, the ray of tree->frames[0]: pushed, it is yet to be traced and shaded; not, its
 * frame is shaded already (the packet path, cl/packet_render.cl, traces camera rays and
 * their shadow rays a packet at a time and hands the rest of each tree to this walk). Each
 * ray of the tree is shaded at the one shadeFrame call below (which traces it and its
 * shadow rays at one traceBvh call), the loop's first step whenever a frame has just been
 * pushed (a GPU compiler inlines every call site). Inline on PoCL as well: there a call of
 * its own cost chess 1% more instructions. */
static inline RAY_INLINED_ON_GPU
float3 walkRayTree(const SceneBuffers* scene, const RayRenderParams* params, RayTree* tree, Ray ray, bool pushed,
                   PixelTrace* counter) {
    Frame* stack = tree->frames;
    int top = 0;
    while (true) {
        Frame* frame = &stack[top];
        if (pushed) {
            shadeFrame(scene, params, tree, top, ray, &ray, counter);
            pushed = false;
        }
        if (frame->nextChild < frame->childCount) {
            if (frame->nextChild++ == 1) { /* the second; the first is in place already (spawnChild) */
                Frame* child = &stack[top + 1];
                const ChildRay* second = &tree->seconds[top];
                child->weightInParent = second->weight;
                child->medium = frame->secondMedium;
                child->enteredIor = second->enteredIor;
                ray.origin = unpackFloat3(second->origin); /* ray.time stays: every ray of the */
                ray.direction = unpackFloat3(second->direction); /* tree sees the scene at one time */
            }
            counter->secondary++;
            ++top;
            pushed = true;
            continue;
        }
        if (top == 0) return unpackFloat3(frame->color);
        float3 folded = unpackFloat3(frame->weightInParent) * clamp(unpackFloat3(frame->color), 0.0f, 1.0f);
        --top;
        stack[top].color = packFloat3(unpackFloat3(stack[top].color) + folded);
    }
}

#ifndef RAY_PACKET_WIDTH /* the packet path: cl/packet_render.cl */
/* The color of one camera ray (walkRayTree). */
static inline RAY_INLINED_ON_GPU
float3 traceCameraRay(const SceneBuffers* scene, const RayRenderParams* params, Ray ray, PixelTrace* counter) {
    RayTree tree;
    counter->primary++;
    return walkRayTree(scene, params, &tree, ray, true, counter);
}
#endif

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

/* A sample's lens: the course's grid (SPEC §3) or one random point of the disk (--dof
 * disk), and how many lens rays it takes (RAY_LENS_GRID_SIDE² on the grid, else 1). */
static inline bool courseLensGrid(const RayRenderParams* params) {
    return params->lens.x > 0.0f && !(params->mode.z & RAY_FEATURE_LENS_DISK);
}

static inline int lensRaysPerSample(const RayRenderParams* params) {
    return courseLensGrid(params) ? RAY_LENS_GRID_SIDE * RAY_LENS_GRID_SIDE : 1;
}

/* Starts the pixel's next sample: numbers it, draws its shutter time from random dimension
 * 4 (shutter, params->lens.z, 0 when nothing moves, times that number) and, with --dof
 * disk, its lens point from dimensions 2 and 3 (0 and 1 are the stratified jitter). */
static inline float2 startSample(const RayRenderParams* params, PixelTrace* counter) {
    uint k = counter->nextSample++;
    counter->sample = k;
    uint seed = (uint)params->counts.w;
    float2 lens = (float2)(0.0f);
    if (params->lens.x > 0.0f && !courseLensGrid(params))
        lens = (float2)(rayRandom(counter->pixel, k, 2u, seed), rayRandom(counter->pixel, k, 3u, seed));
    float shutter = params->lens.z;
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

#ifndef RAY_PACKET_WIDTH /* the packet path: cl/packet_render.cl */
/* One sample of the pixel, unclamped (startSample): the mean of its lens rays' terms, one
 * trace site in a loop. */
static inline RAY_INLINED_ON_GPU
float3 traceSample(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, float sx, float sy,
                          PixelTrace* counter) {
    float2 lens = startSample(params, counter);
    const int lensRays = lensRaysPerSample(params);
    float3 sum = (float3)(0.0f);
    for (int l = 0; l < lensRays; ++l) {
        Ray ray = cameraRay(params, (float)i, (float)j, sx, sy, lensPoint(params, l, lens), counter->time);
        sum += lensRayTerm(params, traceCameraRay(scene, params, ray, counter));
    }
    return sum / (float)lensRays;
}
#endif

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

/* The course's machine, one entry per level of its recursion. A level's square is the
 * quadrant of its parent's that it replaces (courseCorner). */
typedef struct {
    PackedFloat3 quadrant[RAY_COURSE_LEVELS][4]; /* the (clamped) values of a, b, c, d */
    uchar taken[RAY_COURSE_LEVELS];    /* samples taken at the level: 0..4, then 5 once judged */
    uchar toRefine[RAY_COURSE_LEVELS]; /* quadrants still to replace by the next level (bits) */
    uchar refining[RAY_COURSE_LEVELS]; /* the quadrant the next level replaces */
    char level;                        /* the level being sampled; -1 when the pixel is done */
} CourseSampler;

/* The jittered modes (--aa off counts its one sample here). Plain float3: the course's
 * machine is larger, and so sets the union's size. */
typedef struct {
    float3 sum, low, high; /* of the samples taken; low and high of the first four (adaptive) */
    int count, side;       /* samples taken; the side of the grid being sampled */
    int extra;             /* adaptive: whether the k×k grid is being taken */
} JitteredSampler;

/* A pixel uses one mode (params->mode.x), so the two machines share their memory. */
typedef union {
    CourseSampler course;
    JitteredSampler jittered;
} PixelSampler;

static inline void startSampler(PixelSampler* s, const RayRenderParams* params) {
    if (params->mode.x == RAY_AA_COURSE) {
        s->course.level = 0;
        s->course.taken[0] = 0;
        return;
    }
    JitteredSampler* j = &s->jittered;
    j->count = 0;
    /* --aa off counts its one sample and nothing else: the rest is a per-pixel cost there
     * (PoCL: 0.8 M instructions of chess's 132.3 M, most of its pixels missing everything) */
    if (params->mode.x == RAY_AA_OFF) return;
    j->sum = (float3)(0.0f);
    j->low = (float3)(INFINITY);
    j->high = (float3)(-INFINITY);
    j->extra = 0;
    int samples = params->mode.w;
    bool stratified = params->mode.x == RAY_AA_STRATIFIED || samples <= 4;
    j->side = stratified ? max(1, (int)floor(sqrt((float)samples))) : 2;
}

/* The top left corner of the square that the course's level `level` samples: each level
 * above it moved it to the quadrant it refines, by half that level's size. */
static inline float2 courseCorner(const CourseSampler* s, int level) {
    float2 corner = (float2)(0.0f);
    for (int l = 0; l < level; ++l) {
        int q = s->refining[l];
        float halfSize = 1.0f / (float)(1 << l) * 0.5f;
        corner += (float2)((q & 1) ? halfSize : 0.0f, (q & 2) ? halfSize : 0.0f);
    }
    return corner;
}

static inline float3 quadrantValue(const CourseSampler* s, int level, int q) {
    return unpackFloat3(s->quadrant[level][q]);
}

/* The course's machine: the next sample position, or false when the pixel's value is
 * known (in *color). A level whose four samples are in is judged once; its quadrants to
 * refine are then entered one by one, and a finished level hands its mean to its parent. */
static inline bool nextCoursePosition(CourseSampler* s, float2* position, float3* color) {
    while (s->level >= 0) {
        int l = s->level;
        float size = 1.0f / (float)(1 << l);
        if (s->taken[l] < 4) {
            int q = s->taken[l];
            float quarter = size * 0.25f;
            *position = courseCorner(s, l) +
                        (float2)((q & 1) ? 3.0f * quarter : quarter, (q & 2) ? 3.0f * quarter : quarter);
            return true;
        }
        if (s->taken[l] == 4) { /* judged once, before any quadrant is replaced */
            s->toRefine[l] = l + 1 < RAY_COURSE_LEVELS
                                 ? courseSubdivided(quadrantValue(s, l, 0), quadrantValue(s, l, 1),
                                                    quadrantValue(s, l, 2), quadrantValue(s, l, 3))
                                 : 0;
            s->taken[l] = 5;
        }
        if (s->toRefine[l] != 0) {
            int q = 0;
            while (!(s->toRefine[l] & (1 << q))) ++q; /* a, b, c, d in turn */
            s->toRefine[l] &= ~(1 << q);
            s->refining[l] = q;
            s->taken[l + 1] = 0;
            s->level = l + 1;
            continue;
        }
        float3 mean = 0.25f * (quadrantValue(s, l, 0) + quadrantValue(s, l, 1) + quadrantValue(s, l, 2) +
                               quadrantValue(s, l, 3));
        s->level = l - 1;
        if (l == 0) *color = mean;
        else s->quadrant[l - 1][s->refining[l - 1]] = packFloat3(mean);
    }
    return false;
}

/* The jittered modes: sample number s->count (its random numbers pick the jitter) in cell
 * `cell` of the side×side grid being sampled, or false when the pixel's value is known
 * (in *color). */
static inline bool nextJitteredPosition(JitteredSampler* s, const RayRenderParams* params, uint pixel,
                                        float2* position, float3* color) {
    int cell = s->extra ? s->count - 4 : s->count;
    if (cell >= s->side * s->side) {
        bool refine = params->mode.x == RAY_AA_ADAPTIVE && params->mode.w > 4 && !s->extra &&
                      largestChannel(s->high - s->low) > RAY_ADAPTIVE_CONTRAST;
        if (!refine) {
            *color = s->sum / (float)s->count;
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
 * and its color is in *color. */
static inline bool nextSamplePosition(PixelSampler* s, const RayRenderParams* params, uint pixel, float2* position,
                                      float3* color) {
    switch (params->mode.x) {
        case RAY_AA_COURSE: return nextCoursePosition(&s->course, position, color);
        case RAY_AA_STRATIFIED:
        case RAY_AA_ADAPTIVE: return nextJitteredPosition(&s->jittered, params, pixel, position, color);
        default:
            if (s->jittered.count > 0) return false; /* addSample gave *color */
            *position = (float2)(0.5f);
            return true;
    }
}

/* Takes the color of the sample at the position nextSamplePosition gave: clamped, except
 * with --aa off, whose one sample is the pixel's unclamped color (*pixelColor). */
static inline void addSample(PixelSampler* s, const RayRenderParams* params, float3 color, float3* pixelColor) {
    if (params->mode.x == RAY_AA_OFF) {
        *pixelColor = color;
        s->jittered.count++;
        return;
    }
    color = clamp(color, 0.0f, 1.0f);
    if (params->mode.x == RAY_AA_COURSE) {
        CourseSampler* c = &s->course;
        int l = c->level;
        c->quadrant[l][c->taken[l]++] = packFloat3(color);
        return;
    }
    JitteredSampler* j = &s->jittered;
    j->sum += color;
    if (j->count < 4) {
        j->low = fmin(j->low, color);
        j->high = fmax(j->high, color);
    }
    j->count++;
}

#ifndef RAY_PACKET_WIDTH /* the packet path renders blocks: cl/packet_render.cl */
/* The color of pixel (i, j): every sample the antialiasing mode asks for, traced at the one
 * trace site. A call on PoCL: there the work-group function runs the kernel for each
 * work-item in a loop and keeps the private variables of the kernel's own body in arrays
 * with an entry per work-item (the sampler, the ray tree's frames), whose addressing cost
 * chess 3% more instructions than a call with its own stack frame. */
static RAY_CALL_ON_CPU float3 renderPixel(const SceneBuffers* scene, const RayRenderParams* params, int i, int j,
                                           PixelTrace* counter) {
    PixelSampler sampler;
    startSampler(&sampler, params);
    float2 position;
    float3 color; /* given by nextSamplePosition, or with --aa off by addSample, as the loop ends */
    while (nextSamplePosition(&sampler, params, counter->pixel, &position, &color)) {
        float3 sample = traceSample(scene, params, i, j, position.x, position.y, counter); /* the one trace site */
        addSample(&sampler, params, sample, &color);
    }
    return color;
}
#endif
