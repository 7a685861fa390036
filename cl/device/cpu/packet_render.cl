/* The packet path of CPU devices: a work-item renders a block of RAY_PACKET_WIDTH pixels
 * (RAY_PIXEL_BLOCK_WIDTH × RAY_PIXEL_BLOCK_HEIGHT, cl/shared_types.h) and traces their camera
 * rays, and then each light's shadow rays, a packet at a time (traceBvhPacket,
 * cl/device/cpu/packet_trace.cl). Built only where RAY_PACKET_WIDTH is defined
 * (cl/device/variant.h: a CPU device's RAY_CPU_LANES of 4, 8 or 16, which
 * host/opencl/kernel_variant.h chooses); a GPU's work-item renders one pixel (renderPixel),
 * SIMT being its packet.
 *
 * Everything else is the single-ray path's own code, a pixel at a time: each pixel keeps
 * its sampler (any antialiasing mode), takes its samples and lens rays in its own order and
 * numbering, is shaded by shadeHit, sums its lights with nextShadowRay and
 * addUnblockedSample, and walks the rest of its ray tree (reflections, refraction: rays
 * far less coherent than camera and shadow rays) with walkRayTree. Every ray meets the hit
 * the single-ray walk gives it, so the image is the single-ray path's to the bit
 * (tests/cpu_paths.sh compares them). The pixels of a block take their samples together:
 * a pixel whose antialiasing is done sits out the packets of the others. */

#ifdef RAY_PACKET_WIDTH

#define RAY_BLOCK_WIDTH RAY_PIXEL_BLOCK_WIDTH(RAY_PACKET_WIDTH)

/* addUnblockedSample for the lanes of `unblocked` (non-zero: its light sample's shadow ray
 * found no blocker), the highlights' powers taken for every lane at once: pow a lane at a
 * time was a large part of the kernel's time on highlight-heavy scenes (docs/performance.md,
 * "Highlights in vector form"), and PoCL's vector pow is its scalar
 * one in each lane (both its SLEEF code), so each term is the single-ray path's to the bit. */
static inline void addUnblockedSamples(LightSamples* lights, const int* unblocked) {
    float base[RAY_PACKET_WIDTH], shininess[RAY_PACKET_WIDTH], power[RAY_PACKET_WIDTH];
    bool anyHighlight = false;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        const bool highlight = unblocked[l] && lights[l].highlight;
        base[l] = highlight ? highlightBase(&lights[l]) : 0.0f;
        shininess[l] = highlight ? lights[l].shininess : 1.0f;
        anyHighlight |= highlight;
    }
    if (anyHighlight) {
        PacketFloat b = RAY_PACKET_LOAD(base), n = RAY_PACKET_LOAD(shininess);
        /* highlightPower, a lane a sample */
        RAY_PACKET_STORE(select((PacketFloat)(0.0f), pow(b, n), (b > 0.0f) | (n <= 0.0f)), power);
    }
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l)
        if (unblocked[l]) addUnblockedSampleWithPower(&lights[l], anyHighlight ? power[l] : 0.0f);
}

/* shadeFrame for frame `depth` of the trees of `lanes` (non-zero: it has one) at once: their
 * rays, rays[l], go as one packet, then the shadow rays of their hits, a packet for each
 * light sample in turn. next[l] receives each hit's first child ray (spawnChild); each
 * lane's steps are shadeFrame's, the traces aside. */
static RAY_CALL_ON_CPU void packetShadeFrames(const SceneBuffers* scene, const RayRenderParams* params, RayTree* trees,
                                              int depth, const Ray* rays, const int* lanes, PixelTrace* counters,
                                              Ray* next) {
    const bool courseMeshes = (params->features & RAY_FEATURE_COURSE_MESHES) != 0;
    LightSamples lights[RAY_PACKET_WIDTH];
    Ray shadow[RAY_PACKET_WIDTH];
    Hit hits[RAY_PACKET_WIDTH];
    float tMax[RAY_PACKET_WIDTH];
    int lit[RAY_PACKET_WIDTH], waiting[RAY_PACKET_WIDTH];
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        next[l] = shadow[l] = rays[l]; /* a child's ray keeps the camera sample's time (spawnChild) */
        tMax[l] = RAY_INFINITY;
    }
    traceBvhPacket(scene->nodes, scene->cpuNodes, scene->primitives, scene->triangles, scene->motions, rays, tMax,
                   lanes, false, courseMeshes, hits);
    /* Each mesh hit's shading record (its corners' normals and texture coordinates), asked
     * for before the first is read: a dense mesh's hits are scattered through its records,
     * and shadeHit, a lane after another, waited on each one's cache miss in turn. */
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        if (!lanes[l] || hits[l].primitive < 0 || scene->primitives[hits[l].primitive].type != RAY_PRIM_MESH) continue;
        __global const RayTriangleShading* shading = &scene->triangleShading[hits[l].part];
        packetPrefetch(shading);
        packetPrefetch((__global const char*)shading + sizeof(RayTriangleShading) - 1);
    }
    bool anyWaiting = false;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        lit[l] = waiting[l] = 0;
        if (!lanes[l]) continue;
        startFrame(&trees[l].frames[depth]);
        lit[l] = hits[l].primitive >= 0 &&
                 shadeHit(scene, params, &trees[l], depth, rays[l], hits[l], &next[l], &lights[l]);
        waiting[l] = lit[l] && nextShadowRay(&lights[l], scene, params, &counters[l], &shadow[l], &tMax[l]);
        anyWaiting |= waiting[l] != 0;
    }
    while (anyWaiting) {
        traceBvhPacket(scene->nodes, scene->cpuNodes, scene->primitives, scene->triangles, scene->motions, shadow,
                       tMax, waiting, true, false, hits);
        int unblocked[RAY_PACKET_WIDTH];
        for (int l = 0; l < RAY_PACKET_WIDTH; ++l) unblocked[l] = waiting[l] && hits[l].primitive < 0;
        addUnblockedSamples(lights, unblocked);
        anyWaiting = false;
        for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
            if (!waiting[l]) continue;
            waiting[l] = nextShadowRay(&lights[l], scene, params, &counters[l], &shadow[l], &tMax[l]);
            anyWaiting |= waiting[l] != 0;
        }
    }
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l)
        if (lit[l]) addLights(&trees[l].frames[depth], &lights[l]);
}

#ifndef RAY_COHERENT_CHILD_SPAN
#define RAY_COHERENT_CHILD_SPAN 0.5f
#endif

/* Whether the rays of `lanes` point about the same way: no component of their (unit)
 * directions spans more than RAY_COHERENT_CHILD_SPAN. A flat mirror's reflections of a
 * block's pixels are as parallel as the camera rays they come from; a curved surface
 * scatters them, and a scattered packet visits the union of its rays' nodes, more than each
 * ray walks alone in the sixteen-wide tree. */
static inline bool coherentRays(const Ray* rays, const int* lanes) {
    float3 low = (float3)(RAY_INFINITY), high = (float3)(-RAY_INFINITY);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        if (!lanes[l]) continue;
        low = fmin(low, rays[l].direction);
        high = fmax(high, rays[l].direction);
    }
    const float3 span = high - low;
    return fmax(span.x, fmax(span.y, span.z)) <= RAY_COHERENT_CHILD_SPAN;
}

/* Traces camera ray rays[l] of each pixel of `lanes` (non-zero: it has one) through its
 * whole tree: colors[l], as traceCameraRay gives it. The camera rays' frames are shaded a
 * packet at a time, and so are their first children's (walkRayTree's first step down, for
 * every pixel whose camera ray spawned a child) while those stay coherent (coherentRays).
 * The rest of each tree is walkRayTree's, from where the packets left it. */
static RAY_CALL_ON_CPU void tracePacketCameraRays(const SceneBuffers* scene, const RayRenderParams* params,
                                                   const Ray* rays, const int* lanes, PixelTrace* counters,
                                                   float3* colors) {
    RayTree trees[RAY_PACKET_WIDTH];
    Ray next[RAY_PACKET_WIDTH], after[RAY_PACKET_WIDTH];
    int children[RAY_PACKET_WIDTH];
    bool anyChild = false;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l)
        if (lanes[l]) counters[l].primary++;
    packetShadeFrames(scene, params, trees, 0, rays, lanes, counters, next);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        const Frame* frame = &trees[l].frames[0];
        children[l] = lanes[l] && frame->nextChild < frame->childCount;
    }
    const bool together = coherentRays(next, children);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        children[l] = children[l] && together;
        if (!children[l]) continue;
        /* as walkRayTree pushes frame 0's first child, whose ray is in place (spawnChild) */
        trees[l].frames[0].nextChild++;
        counters[l].secondary++;
        anyChild = true;
    }
    if (anyChild) packetShadeFrames(scene, params, trees, 1, next, children, counters, after);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        if (!lanes[l]) continue;
        colors[l] = children[l] ? walkRayTree(scene, params, &trees[l], after[l], 1, &counters[l])
                                : walkRayTree(scene, params, &trees[l], next[l], 0, &counters[l]);
    }
}

/* One pixel of a block, as renderPixel keeps it. */
typedef struct {
    PixelSampler sampler;
    float2 position; /* of the sample being taken */
    float2 lens;     /* its lens point (startSample) */
    float3 sum;      /* of its lens rays' terms so far */
    float3 color;    /* the pixel's, once its sampler is done */
    int i, j;        /* its place in the image */
    bool inside;     /* in the tile and the image: rendered and written */
} BlockPixel;

/* Renders the block whose top left pixel is (x0, y0) of the tile, writing the colors of its
 * pixels that lie in the tile and the image, and the sum of their ray counts to *rayCounts
 * (the block's entry: renderTile). */
static RAY_CALL_ON_CPU void renderBlock(const SceneBuffers* scene, const RayRenderParams* params, int x0, int y0,
                                         __global float4* tileColors, __global uint4* rayCounts) {
    BlockPixel pixels[RAY_PACKET_WIDTH];
    PixelTrace counters[RAY_PACKET_WIDTH];
    int sampling[RAY_PACKET_WIDTH];
    bool anySampling = false;
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        BlockPixel* p = &pixels[l];
        int x = x0 + l % RAY_BLOCK_WIDTH, y = y0 + l / RAY_BLOCK_WIDTH;
        p->i = params->tile.x0 + x;
        p->j = params->tile.y0 + y;
        p->inside = x < params->tile.width && y < params->tile.height && p->i < params->width && p->j < params->height;
        PixelTrace counter = {0u, 0u, 0u, (uint)(p->j * params->width + p->i), 0u, 0u, 0.0f};
        counters[l] = counter;
        startSampler(&p->sampler, params);
        sampling[l] = p->inside && nextSamplePosition(&p->sampler, params, counter.pixel, &p->position, &p->color);
        anySampling |= sampling[l] != 0;
    }
    const int lensRays = lensRaysPerSample(params);
    while (anySampling) {
        for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
            if (!sampling[l]) continue;
            pixels[l].lens = startSample(params, &counters[l]);
            pixels[l].sum = (float3)(0.0f);
        }
        for (int r = 0; r < lensRays; ++r) {
            Ray rays[RAY_PACKET_WIDTH];
            float3 colors[RAY_PACKET_WIDTH];
            for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
                const BlockPixel* p = &pixels[l];
                Ray none = {(float3)(0.0f), (float3)(0.0f, 0.0f, 1.0f), 0.0f}; /* a lane without a ray */
                rays[l] = sampling[l] ? cameraRay(params, (float)p->i, (float)p->j, p->position.x, p->position.y,
                                                  lensPoint(params, r, p->lens), counters[l].time)
                                      : none;
            }
            tracePacketCameraRays(scene, params, rays, sampling, counters, colors);
            for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
                if (!sampling[l]) continue;
                pixels[l].sum += lensRayTerm(params, colors[l]);
            }
        }
        anySampling = false;
        for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
            BlockPixel* p = &pixels[l];
            if (!sampling[l]) continue;
            addSample(&p->sampler, params, p->sum / (float)lensRays, &p->color);
            sampling[l] = nextSamplePosition(&p->sampler, params, counters[l].pixel, &p->position, &p->color);
            anySampling |= sampling[l] != 0;
        }
    }
    uint4 blockRays = (uint4)(0u);
    for (int l = 0; l < RAY_PACKET_WIDTH; ++l) {
        const BlockPixel* p = &pixels[l];
        if (!p->inside) continue;
        int x = x0 + l % RAY_BLOCK_WIDTH, y = y0 + l / RAY_BLOCK_WIDTH;
        int pixel = y * params->tile.width + x; /* the colors hold this tile alone, row by row */
        tileColors[pixel] = (float4)(p->color, 1.0f);
        blockRays += (uint4)(counters[l].primary, counters[l].shadow, counters[l].secondary, 0u);
    }
    *rayCounts = blockRays;
}

#endif /* RAY_PACKET_WIDTH */
