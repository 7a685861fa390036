/* The kernel's entry point, renderTile: a work-item renders one pixel (renderPixel,
 * cl/render.cl), or on a kernel built for packets (-DRAY_PACKET_WIDTH: CPU devices) a block
 * of pixels together (renderBlock, cl/packet_render.cl). */

/* On AMD GCN, at least 4 waves a SIMD: the register budget (64 VGPRs) that keeps enough
 * work-items in flight to hide memory latency. What does not fit spills to scratch, which
 * scripts/kernel_resources.py counts in the kernel's private memory. */
#if defined(__AMDGCN__)
#define RAY_KERNEL_OCCUPANCY __attribute__((amdgpu_waves_per_eu(4)))
#else
#define RAY_KERNEL_OCCUPANCY
#endif

/* Renders one tile: work-item (x, y) is pixel (tile x0 + x, tile y0 + y) of the image and
 * element y * tile width + x of the tile outputs (on the packet path, the block whose top
 * left pixel is (x · block width, y · block height)). Its arguments: the launch parameters, the
 * scene's buffers in the order of their list (cl/shared_types.h RAY_SCENE_BUFFERS), then the
 * tile's outputs; the host numbers them so (host/opencl/kernel_arguments.h). */
#define RAY_SCENE_BUFFER_PARAMETER(Type, name, what) __global const Type* name,
#define RAY_SCENE_BUFFER_NAME(Type, name, what) name,
__kernel RAY_KERNEL_OCCUPANCY void renderTile(RayRenderParams params, RAY_SCENE_BUFFERS(RAY_SCENE_BUFFER_PARAMETER)
                                              __global float4* tileColors, __global uint4* tileRayCounts) {
    SceneBuffers scene = {RAY_SCENE_BUFFERS(RAY_SCENE_BUFFER_NAME)};
#ifdef RAY_PACKET_WIDTH
    /* Work-item l of group g (along each axis) renders block l · groups + g: a group's
     * blocks are spread over the whole tile, every groups-th block, rather than one corner
     * of it. PoCL's threads take a launch's groups in runs (with 16 groups and 2 threads,
     * 8 each), so groups of one corner each left one thread idle while the other rendered
     * the busy half of the tile; spread, the groups cost alike. */
    int blockX = get_local_id(0) * get_num_groups(0) + get_group_id(0);
    int blockY = get_local_id(1) * get_num_groups(1) + get_group_id(1);
    int x0 = blockX * RAY_PIXEL_BLOCK_WIDTH(RAY_PACKET_WIDTH);
    int y0 = blockY * RAY_PIXEL_BLOCK_HEIGHT(RAY_PACKET_WIDTH);
    if (x0 >= params.tile.x || y0 >= params.tile.y) return;
    renderBlock(&scene, &params, x0, y0, tileColors, tileRayCounts);
#else
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= params.tile.x || y >= params.tile.y) return;
    int i = params.image.z + x, j = params.image.w + y;
    if (i >= params.image.x || j >= params.image.y) return;

    PixelTrace counter = {0u, 0u, 0u, (uint)(j * params.image.x + i), 0u, 0u, 0.0f};
    float3 color = renderPixel(&scene, &params, i, j, &counter);
    int pixel = y * params.tile.x + x; /* the outputs hold this tile alone, row by row */
    tileColors[pixel] = (float4)(color, 1.0f);
    tileRayCounts[pixel] = (uint4)(counter.primary, counter.shadow, counter.secondary, 0u);
#endif
}
#undef RAY_SCENE_BUFFER_PARAMETER
#undef RAY_SCENE_BUFFER_NAME
