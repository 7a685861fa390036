#include "opencl/kernel_build.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "opencl/kernel_arguments.h"
#include "render/render_settings.h"

namespace ray::engine {

namespace {

// The test hook RAY_TEST_BVH_SHORT_STACK=N builds the kernel with an N-entry traversal stack
// (cl/traversal/stack.cl BvhStack), so that tests can make every walk overflow and show that the
// fallback finds the same hits. Empty when the hook is off.
std::string shortStackOption(const TestHooks& hooks) {
    const int entries = hooks.bvhShortStackEntries();
    return entries > 0 ? " -DRAY_BVH_SHORT_STACK=" + std::to_string(entries) : "";
}

// Runs a newly built program's kernel once on a tile of no pixels, the scene's buffers bound
// (buildKernelProgram's firstRun): PoCL finishes building a kernel at its first launch,
// where it compiles (or takes from its cache) the work-group function for the launch's
// local size, and PoCL devices must do that one at a time. It also keeps that work out of
// the frame's first tile.
void launchOnNoPixels(const DeviceSlot& slot, const cl::Program& program, const gpu::RayRenderParams& frameParams) {
    cl::Kernel kernel(program, "renderTile");
    gpu::RayRenderParams params = frameParams;
    params.tile = {0, 0, 0, 0};  // every work-item returns before it reads or writes a buffer
    kernel.setArg(kernel_argument::kParams, sizeof(params), &params);
    for (size_t i = 0; i < kSceneBufferCount; ++i)
        kernel.setArg(kernel_argument::kFirstSceneBuffer + cl_uint(i), slot.sceneBuffers[i]);
    cl::Buffer unwritten(slot.context, CL_MEM_WRITE_ONLY, sizeof(cl_float4) + sizeof(cl_uint4));
    kernel.setArg(kernel_argument::kTileColors, unwritten);
    kernel.setArg(kernel_argument::kTileRayCounts, unwritten);
    if (slot.variant.lanes > 1) kernel.setArg(kernel_argument::kBlockQueue, slot.blockQueue);
    const cl::NDRange group(kWorkGroupSide, kWorkGroupSide);
    slot.queue.enqueueNDRangeKernel(kernel, cl::NullRange, group, group);
    slot.queue.finish();
}

}  // namespace

int kernelFrames(int maxDepth) {
    // One frame per bounce plus the camera ray.
    const int needed = std::clamp(maxDepth, 0, kMaxDepth) + 1;
    for (int frames : {5, 11, 17})
        if (needed <= frames) return frames;
    return kMaxDepth + 1;
}

std::string buildOptions(int frames, const KernelVariant& variant, const TestHooks& hooks) {
    // No -cl-fast-relaxed-math: the intersection code relies on IEEE infinities.
    return "-cl-std=CL1.2 -DRAY_MAX_FRAMES=" + std::to_string(frames) + shortStackOption(hooks) +
           variant.buildDefine();
}

DeviceSlot::Program buildDeviceProgram(DeviceSlot& slot, int frames, const gpu::RayRenderParams& frameParams) {
    if (auto seconds = slot.hooks.slowBuild.forDevice(slot.index))
        std::this_thread::sleep_for(std::chrono::seconds(*seconds));
    DeviceSlot::Program p;
    p.program = buildKernelProgram(slot.device, slot.context, buildOptions(frames, slot.variant, slot.hooks),
                                   [&](const cl::Program& program) { launchOnNoPixels(slot, program, frameParams); });
    p.kernel = cl::Kernel(p.program.program, "renderTile");
    p.privateBytes = p.kernel.getWorkGroupInfo<CL_KERNEL_PRIVATE_MEM_SIZE>(slot.device.device);
    return p;
}

}  // namespace ray::engine
