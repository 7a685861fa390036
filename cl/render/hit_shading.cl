/* The shading of one hit (SPEC §4): its color without the lights, the lights' walk started
 * (LightSamples, cl/shading/shading.cl), and the reflected and refracted rays it spawns into
 * the ray tree (cl/render/ray_tree.cl). */

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
    return anyAbove(pathWeight * weight, params->weightThreshold) && anyAbove(weight, 1e-30f);
}

/* The surfaces refraction applies to (SPEC §4): those of transparent objects (Ot != 0). */
static inline bool refracts(int features, float3 transparent) {
    return (features & RAY_FEATURE_REFRACTION) && anyAbove(fabs(transparent), 1e-30f);
}

/* --fresnel (SPEC §4): R, the exact Fresnel reflectance where the ray of frame
 * stack[depth] meets a transparent surface, from the medium it is in into the one beyond
 * (cl/shading/optics.cl). */
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
    if (!(params->features & RAY_FEATURE_FRESNEL)) {
        addRefractedChild(tree, depth, aboveRay, d, p, normal, surfaceNormal, false, materialIor,
                          (float3)(1.0f), params->rayOffset);
        return;
    }
    float r = surfaceReflectance(tree->frames, depth, d, normal, false, materialIor);
    float3 reflectWeight = (float3)(r), transmitWeight = (float3)(1.0f - r);
    if (branchTraced(params, pathWeight, reflectWeight))
        addReflectedChild(tree, depth, aboveRay, d, p, normal, surfaceNormal, reflectWeight, params->rayOffset);
    if (branchTraced(params, pathWeight, transmitWeight))
        addRefractedChild(tree, depth, aboveRay, d, p, normal, surfaceNormal, false, materialIor,
                          transmitWeight, params->rayOffset);
}

/* Shades the hit of the ray of frame tree->frames[depth]: its color without the lights
 * (which *lights starts to sum) and the rays it spawns (spawnChild: the first into the
 * frame above and *next). False when it has no lights to sum (a ray leaving a transparent
 * object). */
static inline bool shadeHit(const SceneBuffers* scene, const RayRenderParams* params, RayTree* tree, int depth,
                            Ray ray, Hit hit, Ray* next, LightSamples* lights) {
    Frame* frame = &tree->frames[depth];
    const bool courseMeshes = (params->features & RAY_FEATURE_COURSE_MESHES) != 0;
    __global const RayPrimitive* prim = &scene->primitives[hit.primitive];
    /* read where it lies: a private copy of the material is loaded whole and held across the
     * shading, in gfx906 scratch */
    __global const RayMaterial* m = &scene->materials[prim->material];
    float3 p = ray.origin + hit.t * ray.direction;
    float3 faceNormal = hit.objectNormal; /* a mesh's: the triangle's, before its shading normal */
    /* --course-meshes: a mesh keeps its face normal */
    if (prim->type == RAY_PRIM_MESH && !courseMeshes)
        hit.objectNormal = meshShadingNormal(scene->triangleShading, hit.part, hit.barycentric);
    /* only a texture or a bump map reads uv: computed for every hit, the sphere's atan2 and
     * asin are a visible part of the instructions of a scene that has neither */
    const bool mapped = (params->features & RAY_FEATURE_TEXTURES) && (m->textureMap >= 0 || m->bumpMap >= 0);
    float2 uv = mapped ? hitUv(scene, prim->type, &hit) : (float2)(0.0f);
    float3 normal = normalToWorld(prim->worldToObject, hit.objectNormal);
    /* The object normal points outward. Which side the ray meets is the surface's own: a
     * bump map tilts the shading normal, not the surface (host/reference/reference_renderer.cpp). */
    bool entering = dot(normal, ray.direction) < 0.0f;
    float3 surfaceNormal = entering ? normal : -normal; /* facing the ray, before a bump map tilts it */
    if ((params->features & RAY_FEATURE_TEXTURES) && m->bumpMap >= 0) { /* bump maps follow the textures switch */
        hit.objectNormal = bumpedObjectNormal(
            scene, m->bumpMap, uv, m->bumpRepeat, objectTangent(scene, prim->type, hit.part, hit.objectPoint),
            bitangentSign(scene, prim->type, hit.part, faceNormal, hit.objectNormal), hit.objectNormal);
        normal = normalToWorld(prim->worldToObject, hit.objectNormal);
    }
    if (!entering) normal = -normal; /* face the incoming ray */
    int features = params->features;
    if (leavesTransparentObject(features, entering, m->transparent.xyz)) {
        transmitFromInside(params, tree, depth, next, ray.direction, p, normal, surfaceNormal, m->ior);
        return false;
    }

    float3 diffuse = params->kd * m->diffuse.xyz;
    if ((features & RAY_FEATURE_TEXTURES) && m->textureMap >= 0) {
        float3 t = (features & RAY_FEATURE_TRILINEAR)
                       ? sampleTrilinear(scene, m->textureMap, uv, m->textureRepeat,
                                         textureFootprint(scene, params, prim, hit.part, hit.t, ray.direction, normal))
                   : (features & RAY_FEATURE_COURSE_FILTER)
                       ? sampleCourseBilinear(scene, m->textureMap, uv, m->textureRepeat)
                       : sampleTexture(scene, m->textureMap, uv, m->textureRepeat,
                                       (features & RAY_FEATURE_BILINEAR) != 0);
        float blend = m->blend;
        diffuse = blend * t + (1.0f - blend) * diffuse; /* the texture term is not scaled by kd */
    }
    frame->color = packFloat3(params->ka * m->ambient.xyz + m->emissive.xyz); /* shadeFrame adds the lights */
    startLights(lights, p, normal, -ray.direction, diffuse, params->ks * m->specular.xyz, m->shininess,
                params->rayOffset);

    if (atDepthLimit(params, depth)) return true;
    float3 pathWeight = pathWeightOf(tree->frames, depth);
    float3 reflectWeight = params->ks * m->reflective.xyz;
    float3 transmitWeight = params->kt * m->transparent.xyz;
    if ((features & RAY_FEATURE_FRESNEL) && refracts(features, m->transparent.xyz)) {
        /* ks·Or·R·I_r + kt·Ot·(1 − R)·I_t; under total internal reflection (R = 1) the
         * transmitted branch has weight 0 and is not traced. */
        float r = surfaceReflectance(tree->frames, depth, ray.direction, normal, entering, m->ior);
        reflectWeight *= r;
        transmitWeight *= 1.0f - r;
    }
    if ((features & RAY_FEATURE_REFLECTIONS) && branchTraced(params, pathWeight, reflectWeight))
        addReflectedChild(tree, depth, next, ray.direction, p, normal, surfaceNormal, reflectWeight,
                          params->rayOffset);
    if ((features & RAY_FEATURE_REFRACTION) && branchTraced(params, pathWeight, transmitWeight))
        addRefractedChild(tree, depth, next, ray.direction, p, normal, surfaceNormal, entering,
                          m->ior, transmitWeight, params->rayOffset);
    return true;
}

