#include "opencl/device_slot.h"

namespace ray::engine {

TileEntries tileEntries(int width, int height, int packetLanes) {
    const size_t pixels = size_t(width) * size_t(height);
    if (packetLanes <= 1) return {pixels, pixels};
    const int blockWidth = RAY_PIXEL_BLOCK_WIDTH(packetLanes), blockHeight = RAY_PIXEL_BLOCK_HEIGHT(packetLanes);
    return {pixels, size_t((width + blockWidth - 1) / blockWidth) * size_t((height + blockHeight - 1) / blockHeight)};
}

void DeviceSlot::releaseScene() {
    sceneBuffers = {};
    bufferVersions = {};
    bufferOwners = {};
    uploaded.reset();
}

// New buffers and host copies, each written through once (the fills run before the next
// launch), so that a kernel and a read find their pages in place: a page's first touch, in
// a kernel's work-items or a read, is dear (docs/performance.md, "First touches in the
// render"). Made when the device prepares for the frame's tiles, it is no longer the first
// tiles' cost.
void DeviceSlot::sizeTileOutput(TileOutput& out, TileEntries tile) {
    const cl_uint zero = 0;
    // Host-allocatable: zero-copy reads on CPU devices (PoCL).
    if (out.pixels < tile.pixels) {
        out.colors = cl::Buffer(context, CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR, tile.pixels * sizeof(cl_float4));
        queue.enqueueFillBuffer(out.colors, zero, 0, tile.pixels * sizeof(cl_float4));
        out.hostColors.assign(tile.pixels, cl_float4{});
        out.pixels = tile.pixels;
    }
    if (out.rayCounts < tile.rayCounts) {
        out.counts = cl::Buffer(context, CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR, tile.rayCounts * sizeof(cl_uint4));
        queue.enqueueFillBuffer(out.counts, zero, 0, tile.rayCounts * sizeof(cl_uint4));
        out.hostCounts.assign(tile.rayCounts, cl_uint4{});
        out.rayCounts = tile.rayCounts;
    }
}

// The programs go under the lock of the PoCL builds: PoCL frees a program's LLVM module as
// it goes, and LLVM 15 must not do that while another thread parses bitcode (a PoCL device
// still building as the process ended, the other done with the frame: the corpus on
// --device all with POCL_DEVICES="pthread pthread" aborted with "LLVM ERROR: out of memory"
// in UpgradeIntrinsicFunction, once or twice a run). While a build holds the lock, they are
// left for the process's end rather than waited for: a cold build takes seconds, and an
// interrupted ray exits at once.
DeviceSlot::~DeviceSlot() {
    const std::unique_lock released = poclCompilerLock(device, false);
    if (device.isPocl && !released.owns_lock()) new std::map<int, Program>(std::move(programs));  // kept
    programs.clear();
}

}  // namespace ray::engine
