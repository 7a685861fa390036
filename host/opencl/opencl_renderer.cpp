#include "opencl/opencl_renderer.h"

#include <chrono>
#include <deque>

#include "core/memory_limits.h"
#include "render/renderer.h"
#include "opencl/scene_packing.h"

namespace ray {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string mebibytes(uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

// Refuses, before any upload, a scene whose buffers exceed what the device allows.
void checkDeviceLimits(const OpenClDevice& device, const PackedScene& packed, size_t imageBytes) {
    struct Buffer {
        const char* what;
        size_t bytes;
    };
    const Buffer buffers[] = {{"BVH nodes", packed.nodes.size() * sizeof(gpu::RayBvhNode)},
                              {"primitives", packed.primitives.size() * sizeof(gpu::RayPrimitive)},
                              {"textures", packed.texels.size()},
                              {"mesh triangles", packed.triangleShading.size() * sizeof(gpu::RayTriangleShading)},
                              {"image", imageBytes}};
    const std::string advice = "; use a smaller scene or image, another device (ray --list-devices), or --device ref";
    for (const Buffer& b : buffers) {
        if (b.bytes > device.maxAllocation)
            throw DeviceError("the scene's " + std::string(b.what) + " need a " + mebibytes(b.bytes) +
                              " buffer, more than the " + mebibytes(device.maxAllocation) + " " +
                              device.description() + " allows in one allocation" + advice);
    }
    // The colors and the ray counts: two buffers of imageBytes each.
    uint64_t total = packed.totalBytes() + 2 * uint64_t(imageBytes);
    if (total > device.globalMemory)
        throw DeviceError("the scene needs " + mebibytes(total) + " of device memory, more than the " +
                          mebibytes(device.globalMemory) + " of " + device.description() + advice);
    // On the host: both buffers read back, and on a CPU device the device's memory too.
    uint64_t hostBytes = 2 * uint64_t(imageBytes) + (device.isCpu ? total : 0);
    if (auto shortfall = hostMemoryShortfall(hostBytes))
        throw DeviceError("rendering on " + device.description() + " " + *shortfall + " on the host" + advice);
}

// OpenCL refuses zero-sized buffers; an empty table gets one unused element.
template <typename T>
cl::Buffer uploadBuffer(const cl::Context& context, const std::vector<T>& data) {
    static const T placeholder{};
    const void* source = data.empty() ? static_cast<const void*>(&placeholder) : data.data();
    size_t bytes = std::max<size_t>(1, data.size()) * sizeof(T);
    return cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<void*>(source));
}

std::string buildOptions(const RenderSettings& settings) {
    // One frame per bounce plus the camera ray (cl/render.cl). No -cl-fast-relaxed-math:
    // the intersection code relies on IEEE infinities.
    return "-cl-std=CL1.2 -DRAY_MAX_FRAMES=" + std::to_string(settings.maxDepth + 1);
}

}  // namespace

Image renderOpenCl(const OpenClDevice& device, const Scene& scene, const RenderSettings& settings,
                   const OpenClRenderOptions& options, RenderStats* stats) {
    PackedScene packed = packScene(scene, settings);
    const size_t pixels = size_t(settings.width) * size_t(settings.height);
    checkDeviceLimits(device, packed, pixels * sizeof(cl_float4));

    KernelProgram program = buildKernelProgram(device, buildOptions(settings));
    Image image(settings.width, settings.height);
    RenderStats local;
    try {
        const cl::Context& context = program.context;
        cl::CommandQueue queue(context, device.device);
        cl::Buffer nodes = uploadBuffer(context, packed.nodes);
        cl::Buffer primitives = uploadBuffer(context, packed.primitives);
        cl::Buffer materials = uploadBuffer(context, packed.materials);
        cl::Buffer lights = uploadBuffer(context, packed.lights);
        cl::Buffer textures = uploadBuffer(context, packed.textures);
        cl::Buffer texels = uploadBuffer(context, packed.texels);
        cl::Buffer triangles = uploadBuffer(context, packed.triangles);
        cl::Buffer triangleShading = uploadBuffer(context, packed.triangleShading);
        cl::Buffer motions = uploadBuffer(context, packed.motions);  // one placeholder when nothing moves
        // Host-allocatable, so that mapping them below is zero-copy on CPU devices (PoCL),
        // where reading them into fresh vectors cost two 16-byte-per-pixel copies and
        // their page faults (~10 ms of a 0.12 s chess.xml render at 1024x768).
        cl::Buffer pixelsOut(context, CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR, pixels * sizeof(cl_float4));
        cl::Buffer counts(context, CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR, pixels * sizeof(cl_uint4));

        cl::Kernel kernel(program.program, "renderTile");
        gpu::RayRenderParams params = makeRenderParams(scene, settings, packed);
        kernel.setArg(1, nodes);
        kernel.setArg(2, primitives);
        kernel.setArg(3, materials);
        kernel.setArg(4, lights);
        kernel.setArg(5, textures);
        kernel.setArg(6, texels);
        kernel.setArg(7, pixelsOut);
        kernel.setArg(8, counts);
        kernel.setArg(9, triangles);
        kernel.setArg(10, triangleShading);
        kernel.setArg(11, motions);

        auto renderStart = Clock::now();
        const int tile = std::max(8, options.tileSize);
        const int tilesX = (settings.width + tile - 1) / tile, tilesY = (settings.height + tile - 1) / tile;
        const int tileCount = tilesX * tilesY;
        const size_t group = size_t(options.workGroupSize);
        auto roundUp = [](size_t n, size_t m) { return (n + m - 1) / m * m; };
        // A few tiles stay queued ahead of the one being waited for, so the device never
        // idles between launches, while cancelling still takes effect within a few tiles.
        constexpr size_t kTilesInFlight = 4;
        std::deque<cl::Event> inFlight;
        int done = 0, launched = 0;
        auto waitForOldest = [&] {
            inFlight.front().wait();
            inFlight.pop_front();
            if (options.progress) options.progress(double(++done) / double(tileCount));
        };
        for (int t = 0; t < tileCount; ++t) {
            // Cancelled: stop launching; the tiles in flight finish (a kernel cannot be
            // stopped) and the rest of the image stays black (cleared below).
            if (options.cancel && options.cancel->load()) break;
            const int tx = t % tilesX, ty = t / tilesX;
            params.image.z = tx * tile;
            params.image.w = ty * tile;
            params.tile = {std::min(tile, settings.width - tx * tile), std::min(tile, settings.height - ty * tile), 0, 0};
            kernel.setArg(0, sizeof(params), &params);  // captured at enqueue time
            cl::Event event;
            queue.enqueueNDRangeKernel(kernel, cl::NullRange,
                                       cl::NDRange(roundUp(size_t(params.tile.x), group), roundUp(size_t(params.tile.y), group)),
                                       cl::NDRange(group, group), nullptr, &event);
            queue.flush();
            inFlight.push_back(event);
            ++launched;
            if (inFlight.size() >= kTilesInFlight) waitForOldest();
        }
        while (!inFlight.empty()) waitForOldest();
        auto* rgba = static_cast<cl_float4*>(
            queue.enqueueMapBuffer(pixelsOut, CL_TRUE, CL_MAP_READ, 0, pixels * sizeof(cl_float4)));
        auto* rayCounts =
            static_cast<cl_uint4*>(queue.enqueueMapBuffer(counts, CL_TRUE, CL_MAP_READ, 0, pixels * sizeof(cl_uint4)));
        local.renderSeconds = secondsSince(renderStart);
        // The buffers are not initialised: pixels of tiles never launched are left black
        // and uncounted.
        auto launchedTile = [&](size_t p) {
            const int x = int(p % size_t(settings.width)), y = int(p / size_t(settings.width));
            return (y / tile) * tilesX + x / tile < launched;
        };
        const bool complete = launched == tileCount;
        for (size_t p = 0; p < pixels; ++p) {
            if (!complete && !launchedTile(p)) continue;
            for (int c = 0; c < 3; ++c) image.rgb[p * 3 + size_t(c)] = rgba[p].s[c];
            local.primaryRays += rayCounts[p].s[0];
            local.shadowRays += rayCounts[p].s[1];
            local.secondaryRays += rayCounts[p].s[2];
        }
        queue.enqueueUnmapMemObject(pixelsOut, rgba);
        queue.enqueueUnmapMemObject(counts, rayCounts);
        queue.finish();
    } catch (const cl::Error& e) {
        std::string what = openClErrorName(e.err());
        std::string advice = (e.err() == CL_MEM_OBJECT_ALLOCATION_FAILURE || e.err() == CL_OUT_OF_RESOURCES ||
                              e.err() == CL_OUT_OF_HOST_MEMORY)
                                 ? "the device ran out of memory; try a smaller image or scene, or --device ref"
                                 : "try another device (ray --list-devices) or --device ref";
        throw DeviceError(device.description() + ": " + e.what() + " failed with " + what + "; " + advice);
    }
    local.device = device.description();
    local.bvhBuildSeconds = packed.bvhBuildSeconds;
    local.kernelBuildSeconds = program.buildSeconds;
    if (stats) *stats = local;
    return image;
}

}  // namespace ray
