/* One pixel a work-item (every build but a packet build: cl/device/variant.h): its samples
 * (cl/render/antialiasing.cl), each the mean of its lens rays (cl/render/camera.cl), each
 * traced through its tree (cl/render/tree_walk.cl). A packet build renders blocks of pixels
 * instead (cl/device/cpu/packet_render.cl). */

#ifndef RAY_PACKET_WIDTH
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

/* The color of pixel (i, j): every sample the antialiasing mode asks for, traced at the one
 * trace site. A call on PoCL: there the work-group function runs the kernel for each
 * work-item in a loop and keeps the private variables of the kernel's own body in arrays
 * with an entry per work-item (the sampler, the ray tree's frames), whose addressing costs
 * more instructions than a call with its own stack frame (docs/performance.md). */
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
