/* The kernel: one work-item per pixel. A pixel's samples (SPEC §3) each trace a tree of
 * rays (a reflected and a refracted branch per hit) with an explicit stack, since
 * OpenCL C has no recursion. */

#ifndef RAY_MAX_FRAMES
#define RAY_MAX_FRAMES 5 /* max depth + 1; the host passes -DRAY_MAX_FRAMES */
#endif

/* One ray of the tree awaiting its children. Its color is folded into its parent, clamped
 * to [0, 1] and weighted, once all of its children are folded into it (SPEC §4: I_r is
 * clamped before it is weighted). */
typedef struct {
    float3 color;          /* local shading plus the children folded in so far */
    float3 pathWeight;     /* product of the weights from the camera ray to this one */
    float3 weightInParent; /* ks·Or (or kt·Ot) of the parent for this ray */
    Ray children[2];
    float3 childWeights[2];
    MediumStack media;          /* the media this frame's ray travels through */
    MediumStack childMedia[2];  /* and those of its children (cl/optics.cl) */
    int childCount, nextChild, depth;
} Frame;

inline bool anyAbove(float3 v, float threshold) {
    return v.x >= threshold || v.y >= threshold || v.z >= threshold;
}

/* The kt·Ot branch (SPEC §4): the ray refracted by Snell's law into the medium beyond the
 * surface, or, under total internal reflection, the mirrored ray, which stays in the
 * medium it came from. normal faces the incoming direction d. */
void addRefractedChild(Frame* frame, float3 d, float3 p, float3 normal, bool entering, float materialIor,
                       float3 weight, float epsilon) {
    MediumStack beyond;
    float n1 = iorBefore(&frame->media, entering, materialIor);
    float n2 = iorBeyond(&frame->media, entering, materialIor, &beyond);
    float3 transmitted;
    Ray child;
    if (refractDirection(d, normal, n1, n2, &transmitted)) {
        child.origin = offsetFromSurface(p, -normal, epsilon); /* start on the far side */
        child.direction = transmitted;
        frame->childMedia[frame->childCount] = beyond;
    } else {
        child.origin = offsetFromSurface(p, normal, epsilon);
        child.direction = d - 2.0f * dot(d, normal) * normal;
        frame->childMedia[frame->childCount] = frame->media;
    }
    frame->children[frame->childCount] = child;
    frame->childWeights[frame->childCount] = weight;
    frame->childCount++;
}

/* The mirrored ray (I_r), which stays in the medium it came from (traceCameraRay sets its time). */
void addReflectedChild(Frame* frame, float3 d, float3 p, float3 normal, float3 weight, float epsilon) {
    Ray reflected = {offsetFromSurface(p, normal, epsilon), d - 2.0f * dot(d, normal) * normal, 0.0f};
    frame->children[frame->childCount] = reflected;
    frame->childWeights[frame->childCount] = weight;
    frame->childMedia[frame->childCount] = frame->media;
    frame->childCount++;
}

/* Whether a branch of weight `weight` below this frame is traced: --threshold cuts it when
 * its path weight is below the threshold in every channel, and a zero weight is no branch. */
inline bool branchTraced(const RayRenderParams* params, const Frame* frame, float3 weight) {
    return anyAbove(frame->pathWeight * weight, params->limits.x) && anyAbove(weight, 1e-30f);
}

/* The surfaces refraction applies to (SPEC §4): those of transparent objects (Ot != 0). */
inline bool refracts(int features, float3 transparent) {
    return (features & RAY_FEATURE_REFRACTION) && anyAbove(fabs(transparent), 1e-30f);
}

/* --fresnel (SPEC §4): R, the exact Fresnel reflectance where the frame's ray meets a
 * transparent surface, from the medium it is in into the one beyond (cl/optics.cl). */
inline float surfaceReflectance(const Frame* frame, float3 d, float3 normal, bool entering, float materialIor) {
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
inline bool leavesTransparentObject(int features, bool entering, float3 transparent) {
    return !entering && refracts(features, transparent);
}

void transmitFromInside(const RayRenderParams* params, Frame* frame, float3 d, float3 p, float3 normal,
                        float materialIor) {
    if (frame->depth >= params->mode.y) return; /* no bounce left: I_t is black */
    if (!(params->mode.z & RAY_FEATURE_FRESNEL)) {
        addRefractedChild(frame, d, p, normal, false, materialIor, (float3)(1.0f), params->limits.y);
        return;
    }
    float r = surfaceReflectance(frame, d, normal, false, materialIor);
    float3 reflectWeight = (float3)(r), transmitWeight = (float3)(1.0f - r);
    if (branchTraced(params, frame, reflectWeight))
        addReflectedChild(frame, d, p, normal, reflectWeight, params->limits.y);
    if (branchTraced(params, frame, transmitWeight))
        addRefractedChild(frame, d, p, normal, false, materialIor, transmitWeight, params->limits.y);
}

/* Traces frame's ray, shades the hit and records the rays it spawns. */
void shadeFrame(const SceneBuffers* scene, const RayRenderParams* params, Frame* frame, Ray ray, PixelTrace* counter) {
    frame->color = (float3)(0.0f);
    frame->childCount = 0;
    frame->nextChild = 0;
    Hit hit;
    const bool courseMeshes = (params->mode.z & RAY_FEATURE_COURSE_MESHES) != 0;
    if (!traceBvh(scene->nodes, scene->primitives, scene->triangles, scene->motions, ray, RAY_INFINITY, false,
                  courseMeshes, &hit))
        return;

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
        transmitFromInside(params, frame, ray.direction, p, normal, m.specular.w);
        return;
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
    frame->color = k.x * m.ambient.xyz + m.emissive.xyz +
                   directLighting(scene, params, p, normal, -ray.direction, diffuse, k.z * m.specular.xyz,
                                  m.ambient.w, counter);

    if (frame->depth >= params->mode.y) return;
    float3 reflectWeight = k.z * m.reflective.xyz;
    float3 transmitWeight = k.w * m.transparent.xyz;
    if ((features & RAY_FEATURE_FRESNEL) && refracts(features, m.transparent.xyz)) {
        /* ks·Or·R·I_r + kt·Ot·(1 − R)·I_t; under total internal reflection (R = 1) the
         * transmitted branch has weight 0 and is not traced. */
        float r = surfaceReflectance(frame, ray.direction, normal, entering, m.specular.w);
        reflectWeight *= r;
        transmitWeight *= 1.0f - r;
    }
    if ((features & RAY_FEATURE_REFLECTIONS) && branchTraced(params, frame, reflectWeight))
        addReflectedChild(frame, ray.direction, p, normal, reflectWeight, params->limits.y);
    if ((features & RAY_FEATURE_REFRACTION) && branchTraced(params, frame, transmitWeight))
        addRefractedChild(frame, ray.direction, p, normal, entering, m.specular.w, transmitWeight, params->limits.y);
}

/* The color of one camera ray: the tree of reflected rays below it, depth first. */
float3 traceCameraRay(const SceneBuffers* scene, const RayRenderParams* params, Ray ray, PixelTrace* counter) {
    Frame stack[RAY_MAX_FRAMES];
    int top = 0;
    stack[0].depth = 0;
    stack[0].pathWeight = (float3)(1.0f);
    stack[0].weightInParent = (float3)(1.0f);
    stack[0].media.count = 0; /* the camera is in air */
    counter->primary++;
    shadeFrame(scene, params, &stack[0], ray, counter);
    while (true) {
        Frame* frame = &stack[top];
        if (frame->nextChild < frame->childCount && top + 1 < RAY_MAX_FRAMES) {
            int c = frame->nextChild++;
            Frame* child = &stack[top + 1];
            child->depth = frame->depth + 1;
            child->weightInParent = frame->childWeights[c];
            child->pathWeight = frame->pathWeight * frame->childWeights[c];
            child->media = frame->childMedia[c];
            counter->secondary++;
            Ray childRay = frame->children[c];
            childRay.time = ray.time; /* every ray of the tree sees the scene at its camera sample's time */
            shadeFrame(scene, params, child, childRay, counter);
            ++top;
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
inline Ray cameraRay(const RayRenderParams* params, float i, float j, float sx, float sy, float2 lens, float time) {
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
inline float3 traceSample(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, float sx, float sy,
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

inline float3 samplePixel(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, float sx, float sy,
                          PixelTrace* counter) {
    return clamp(traceSample(scene, params, i, j, sx, sy, counter), 0.0f, 1.0f);
}

inline float contrast(float3 a, float3 b, float3 c, float3 d) {
    float3 spread = fmax(fmax(a, b), fmax(c, d)) - fmin(fmin(a, b), fmin(c, d));
    return fmax(spread.x, fmax(spread.y, spread.z));
}

/* Whether two samples differ by more than RAY_COURSE_AA_CONTRAST in some channel. */
inline bool courseDiffers(float3 a, float3 b) {
    float3 d = fabs(a - b);
    return fmax(d.x, fmax(d.y, d.z)) > RAY_COURSE_AA_CONTRAST;
}

/* The course's adaptive antialiasing (README, Conventions, "Antialiasing";
 * host/reference/course_sampling.cpp): value(square, level) samples the centres of the
 * square's four quadrants a (top left), b (top right), c (bottom left), d (bottom right);
 * where level < 3, a quadrant whose sample differs from a horizontal or vertical neighbour's
 * (a–b, c–d, a–c, b–d; not the diagonals) by more than RAY_COURSE_AA_CONTRAST in some channel
 * is replaced by value(quadrant, level + 1). The result is the mean of the four. Written as
 * three nested levels because OpenCL C has no recursion. */
float3 courseSquare3(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, float x0, float y0,
                     float size, PixelTrace* counter) {
    float q = size * 0.25f;
    return 0.25f * (samplePixel(scene, params, i, j, x0 + q, y0 + q, counter) +
                    samplePixel(scene, params, i, j, x0 + 3.0f * q, y0 + q, counter) +
                    samplePixel(scene, params, i, j, x0 + q, y0 + 3.0f * q, counter) +
                    samplePixel(scene, params, i, j, x0 + 3.0f * q, y0 + 3.0f * q, counter));
}

/* Which quadrants of a, b, c, d the course subdivides: bit 0 a, 1 b, 2 c, 3 d. */
inline int courseSubdivided(float3 a, float3 b, float3 c, float3 d) {
    int bits = 0;
    if (courseDiffers(a, b)) bits |= 1 | 2;
    if (courseDiffers(c, d)) bits |= 4 | 8;
    if (courseDiffers(a, c)) bits |= 1 | 4;
    if (courseDiffers(b, d)) bits |= 2 | 8;
    return bits;
}

float3 courseSquare2(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, float x0, float y0,
                     float size, PixelTrace* counter) {
    float q = size * 0.25f, h = size * 0.5f;
    float3 a = samplePixel(scene, params, i, j, x0 + q, y0 + q, counter);
    float3 b = samplePixel(scene, params, i, j, x0 + 3.0f * q, y0 + q, counter);
    float3 c = samplePixel(scene, params, i, j, x0 + q, y0 + 3.0f * q, counter);
    float3 d = samplePixel(scene, params, i, j, x0 + 3.0f * q, y0 + 3.0f * q, counter);
    int bits = courseSubdivided(a, b, c, d);
    if (bits & 1) a = courseSquare3(scene, params, i, j, x0, y0, h, counter);
    if (bits & 2) b = courseSquare3(scene, params, i, j, x0 + h, y0, h, counter);
    if (bits & 4) c = courseSquare3(scene, params, i, j, x0, y0 + h, h, counter);
    if (bits & 8) d = courseSquare3(scene, params, i, j, x0 + h, y0 + h, h, counter);
    return 0.25f * (a + b + c + d);
}

float3 coursePixel(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, PixelTrace* counter) {
    float3 a = samplePixel(scene, params, i, j, 0.25f, 0.25f, counter);
    float3 b = samplePixel(scene, params, i, j, 0.75f, 0.25f, counter);
    float3 c = samplePixel(scene, params, i, j, 0.25f, 0.75f, counter);
    float3 d = samplePixel(scene, params, i, j, 0.75f, 0.75f, counter);
    int bits = courseSubdivided(a, b, c, d);
    if (bits & 1) a = courseSquare2(scene, params, i, j, 0.0f, 0.0f, 0.5f, counter);
    if (bits & 2) b = courseSquare2(scene, params, i, j, 0.5f, 0.0f, 0.5f, counter);
    if (bits & 4) c = courseSquare2(scene, params, i, j, 0.0f, 0.5f, 0.5f, counter);
    if (bits & 8) d = courseSquare2(scene, params, i, j, 0.5f, 0.5f, 0.5f, counter);
    return 0.25f * (a + b + c + d);
}

/* Stratified jittered samples: an n×n grid (n = floor(sqrt(samples))), one jittered sample
 * per cell warped through the tent reconstruction filter (rayTentOffset), averaged. */
float3 stratifiedPixel(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, PixelTrace* counter) {
    int n = max(1, (int)floor(sqrt((float)params->mode.w)));
    uint pixel = counter->pixel;
    uint seed = (uint)params->counts.w;
    float3 sum = (float3)(0.0f);
    for (int s = 0; s < n * n; ++s) {
        float sx = rayTentOffset(((float)(s % n) + rayRandom(pixel, (uint)s, 0u, seed)) / (float)n);
        float sy = rayTentOffset(((float)(s / n) + rayRandom(pixel, (uint)s, 1u, seed)) / (float)n);
        sum += samplePixel(scene, params, i, j, sx, sy, counter);
    }
    return sum / (float)(n * n);
}

/* The sample of cell `cell` of a side×side grid, jittered by the random numbers of sample
 * number `number` (host/reference/course_sampling.cpp jitteredCell). */
inline float3 jitteredSample(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, int cell, int side,
                             uint number, PixelTrace* counter) {
    uint seed = (uint)params->counts.w;
    float sx = rayTentOffset(((float)(cell % side) + rayRandom(counter->pixel, number, 0u, seed)) / (float)side);
    float sy = rayTentOffset(((float)(cell / side) + rayRandom(counter->pixel, number, 1u, seed)) / (float)side);
    return samplePixel(scene, params, i, j, sx, sy, counter);
}

/* --aa adaptive (host/reference/course_sampling.h sampleAdaptive): 2×2 jittered samples; where they
 * spread by more than RAY_ADAPTIVE_CONTRAST, a k×k jittered grid more (sample numbers 4..);
 * the mean of every sample taken. */
float3 adaptivePixel(const SceneBuffers* scene, const RayRenderParams* params, int i, int j, PixelTrace* counter) {
    int samples = params->mode.w;
    if (samples <= 4) return stratifiedPixel(scene, params, i, j, counter);
    float3 a = jitteredSample(scene, params, i, j, 0, 2, 0u, counter);
    float3 b = jitteredSample(scene, params, i, j, 1, 2, 1u, counter);
    float3 c = jitteredSample(scene, params, i, j, 2, 2, 2u, counter);
    float3 d = jitteredSample(scene, params, i, j, 3, 2, 3u, counter);
    float3 sum = a + b + c + d;
    int count = 4;
    if (contrast(a, b, c, d) > RAY_ADAPTIVE_CONTRAST) {
        int side = max(1, (int)floor(sqrt((float)samples)));
        for (int cell = 0; cell < side * side; ++cell)
            sum += jitteredSample(scene, params, i, j, cell, side, (uint)(4 + cell), counter);
        count += side * side;
    }
    return sum / (float)count;
}

/* Renders one tile: work-item (x, y) is pixel (tile x0 + x, tile y0 + y) of the image and
 * element y * tile width + x of the tile outputs. */
__kernel void renderTile(RayRenderParams params, __global const RayWideBvhNode* nodes,
                         __global const RayPrimitive* primitives, __global const RayMaterial* materials,
                         __global const RayLight* lights, __global const RayTexture* textures,
                         __global const uchar4* texels, __global float4* tileColors, __global uint4* tileRayCounts,
                         __global const RayTriangle* triangles, __global const RayTriangleShading* triangleShading,
                         __global const float4* motions) {
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= params.tile.x || y >= params.tile.y) return;
    int i = params.image.z + x, j = params.image.w + y;
    if (i >= params.image.x || j >= params.image.y) return;

    SceneBuffers scene = {nodes, primitives, materials, lights, textures, texels, triangles, triangleShading, motions};
    PixelTrace counter = {0u, 0u, 0u, (uint)(j * params.image.x + i), 0u, 0u, 0.0f};
    float3 color;
    switch (params.mode.x) {
        case RAY_AA_COURSE: color = coursePixel(&scene, &params, i, j, &counter); break;
        case RAY_AA_STRATIFIED: color = stratifiedPixel(&scene, &params, i, j, &counter); break;
        case RAY_AA_ADAPTIVE: color = adaptivePixel(&scene, &params, i, j, &counter); break;
        default: /* unclamped, for float outputs */
            color = traceSample(&scene, &params, i, j, 0.5f, 0.5f, &counter);
    }
    int pixel = y * params.tile.x + x; /* the outputs hold this tile alone, row by row */
    tileColors[pixel] = (float4)(color, 1.0f);
    tileRayCounts[pixel] = (uint4)(counter.primary, counter.shadow, counter.secondary, 0u);
}
