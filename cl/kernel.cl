/* The kernel's entry point, renderTile: a work-item renders one pixel (renderPixel,
 * cl/render/pixel.cl), or in a packet build (CPU devices: cl/device/variant.h) a block of
 * pixels together (renderBlock, cl/device/cpu/packet_render.cl). */

/* On AMD GCN, at least 4 waves a SIMD: the register budget (64 VGPRs) that keeps enough
 * work-items in flight to hide memory latency. What does not fit spills to scratch, which
 * scripts/kernel_resources.py counts in the kernel's private memory. */
#if defined(__AMDGCN__)
#define RAY_KERNEL_OCCUPANCY __attribute__((amdgpu_waves_per_eu(4)))
#else
#define RAY_KERNEL_OCCUPANCY
#endif

/* Renders one tile: work-item (x, y) is pixel (tile x0 + x, tile y0 + y) of the image and
 * element y * tile width + x of the tile outputs. On the packet path the ray counts are a
 * block's, tileRayCounts[b] for block b of the tile's rows of blocks: the host sums them for
 * the tile alone, and a block's entry is one of RAY_PACKET_WIDTH pixels' to read back and
 * to hold. Its arguments: the launch parameters, the scene's buffers in the order of their
 * list (cl/shared_types.h RAY_SCENE_BUFFERS), then the tile's outputs, and on the packet
 * path the block queue; the host numbers them so (host/opencl/kernel_arguments.h).
 *
 * On the packet path the work-items take the tile's blocks of pixels from a queue, one at
 * a time in the order of the tile's rows: blockQueue[0] counts the blocks taken (the host
 * launches a work-group a compute unit, and the first work-item of each takes blocks while
 * any are left). PoCL's threads take a launch's work-groups in runs, half of them each with
 * 2 threads, so a fixed share of the blocks left one thread idle at the end of every tile
 * while the other finished a busier share. blockQueue[1] counts the work-items done: the
 * last one empties the queue for the next launch, which the in-order queue runs after this. */
#define RAY_SCENE_BUFFER_PARAMETER(Type, name, what, readers) __global const Type* name,
#define RAY_SCENE_BUFFER_NAME(Type, name, what, readers) name,
__kernel RAY_KERNEL_OCCUPANCY void renderTile(RayRenderParams params, RAY_SCENE_BUFFERS(RAY_SCENE_BUFFER_PARAMETER)
                                              __global float4* tileColors, __global uint4* tileRayCounts
#ifdef RAY_PACKET_WIDTH
                                              , __global volatile uint* blockQueue
#endif
) {
    SceneBuffers scene = {RAY_SCENE_BUFFERS(RAY_SCENE_BUFFER_NAME)};
#ifdef RAY_PACKET_WIDTH
    const int blockWidth = RAY_PIXEL_BLOCK_WIDTH(RAY_PACKET_WIDTH), blockHeight = RAY_PIXEL_BLOCK_HEIGHT(RAY_PACKET_WIDTH);
    const uint blocksAcross = (uint)((params.tile.width + blockWidth - 1) / blockWidth);
    const uint blocks = blocksAcross * (uint)((params.tile.height + blockHeight - 1) / blockHeight);
    for (uint b = atomic_inc(&blockQueue[0]); b < blocks; b = atomic_inc(&blockQueue[0]))
        renderBlock(&scene, &params, (int)(b % blocksAcross) * blockWidth, (int)(b / blocksAcross) * blockHeight,
                    tileColors, &tileRayCounts[b]);
    if (atomic_inc(&blockQueue[1]) + 1u == (uint)(get_global_size(0) * get_global_size(1))) {
        atomic_xchg(&blockQueue[0], 0u);
        atomic_xchg(&blockQueue[1], 0u);
    }
#else
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= params.tile.width || y >= params.tile.height) return;
    int i = params.tile.x0 + x, j = params.tile.y0 + y;
    if (i >= params.width || j >= params.height) return;

    PixelTrace counter = {0u, 0u, 0u, (uint)(j * params.width + i), 0u, 0u, 0.0f};
    float3 color = renderPixel(&scene, &params, i, j, &counter);
    int pixel = y * params.tile.width + x; /* the outputs hold this tile alone, row by row */
    tileColors[pixel] = (float4)(color, 1.0f);
    tileRayCounts[pixel] = (uint4)(counter.primary, counter.shadow, counter.secondary, 0u);
#endif
}
#undef RAY_SCENE_BUFFER_PARAMETER
#undef RAY_SCENE_BUFFER_NAME
