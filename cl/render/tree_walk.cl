/* Tracing a camera ray's tree: each frame's ray and its shadow rays at one trace site
 * (shadeFrame), the frames depth first (walkRayTree). */

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
    const bool courseMeshes = (params->features & RAY_FEATURE_COURSE_MESHES) != 0;
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
 * `ray`, the ray of tree->frames[0]: pushed (top -1), it is yet to be traced and shaded;
 * else the frames 0 to top are shaded already, and ray is frame top's first child (the
 * packet path, cl/device/cpu/packet_render.cl, traces camera rays, their first children and
 * their shadow rays a packet at a time and hands the rest of each tree to this walk). Each
 * ray of the tree is shaded at the one shadeFrame call below (which traces it and its
 * shadow rays at one traceBvh call), the loop's first step whenever a frame has just been
 * pushed (a GPU compiler inlines every call site). Inline on PoCL as well: there a call of
 * its own costs more instructions than it saves. */
static inline RAY_INLINED_ON_GPU
float3 walkRayTree(const SceneBuffers* scene, const RayRenderParams* params, RayTree* tree, Ray ray, int top,
                   PixelTrace* counter) {
    Frame* stack = tree->frames;
    bool pushed = top < 0;
    if (pushed) top = 0;
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

#ifndef RAY_PACKET_WIDTH /* the packet path: cl/device/cpu/packet_render.cl */
/* The color of one camera ray (walkRayTree). */
static inline RAY_INLINED_ON_GPU
float3 traceCameraRay(const SceneBuffers* scene, const RayRenderParams* params, Ray ray, PixelTrace* counter) {
    RayTree tree;
    counter->primary++;
    return walkRayTree(scene, params, &tree, ray, -1, counter);
}
#endif

