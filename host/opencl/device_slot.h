// What one device of the OpenCL engine keeps from frame to frame: its context, queue,
// uploaded scene, programs and tile outputs, and the mailbox through which the engine posts
// it frames. Shared by the engine and the device's thread (device_thread.h), which may
// outlive the engine: a hung device's thread cannot be joined (opencl_engine.h).
#pragma once

#include <array>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/test_hooks.h"
#include "opencl/kernel_variant.h"
#include "opencl/opencl_device.h"
#include "opencl/scene_packing.h"

namespace ray::engine {

struct Frame;

// Launches a device keeps in flight: enough that it never idles between them.
constexpr size_t kTilesInFlight = 4;
// A launch's work-groups are kWorkGroupSide x kWorkGroupSide work-items: PoCL left alone
// picks groups of one work-item; 8x8 suits CPUs and GPUs.
constexpr size_t kWorkGroupSide = 8;

// What a launch writes for a tile of width x height: a color a pixel, and ray counts a
// work-item (a pixel's, or on the packet path a block's: cl/kernel.cl).
struct TileEntries {
    size_t pixels = 0, rayCounts = 0;
};
TileEntries tileEntries(int width, int height, int packetLanes);

struct DeviceSlot {
    OpenClDevice device;
    int index = 0;    // position in the engine's selection
    TestHooks hooks;  // the engine's (core/test_hooks.h): its own copy, as the thread may outlive the engine
    KernelVariant variant;  // what its kernel runs (kernelVariantFor): the kernel's build, launches and tables

    // The thread's mailbox, under `mutex`.
    std::mutex mutex;
    std::condition_variable wake;
    std::shared_ptr<Frame> frame;  // the frame to serve next
    uint64_t frameNumber = 0;      // that frame's number: a new one wakes the thread
    bool stop = false;             // the engine is gone
    bool busy = false;             // serving a frame (preparing, rendering or hung)
    bool dropped = false, hung = false;
    std::string failure;           // why it was dropped
    bool failureReported = false;  // in some frame's warnings
    std::thread thread;

    // Touched only by the thread (or by the engine while the thread is idle).
    cl::Context context;
    cl::CommandQueue queue;
    std::shared_ptr<const PackedScene> uploaded;  // the packing the scene's buffers are up to date with
    size_t checkedTilePixels = 0;  // the tile size checkDeviceLimits last passed with them
    // The scene's buffers, in the order of PackedScene::forEachBuffer (renderTile's), each
    // with the version of the table it holds and, on a CPU device, which reads the table in
    // place, the packing that table is in: after an edit a buffer whose table kept its
    // version is kept (a CPU device's made again over the new packing: scene_upload.h).
    std::array<cl::Buffer, kSceneBufferCount> sceneBuffers;
    std::array<uint64_t, kSceneBufferCount> bufferVersions{};
    std::array<std::shared_ptr<const PackedScene>, kSceneBufferCount> bufferOwners;
    // Lets go of the scene's buffers: before the packed tables they may use in place change.
    void releaseScene();
    // Launch k writes its tile into outputs[k % kTilesInFlight]: tile-sized buffers, so a
    // frame costs the device (and, on a CPU device, the host) a few tiles, not two
    // full-frame copies of the image (32 bytes a pixel: 25 MB at 1024x768, 265 MB at 4K).
    // Each also holds the host copies its reads fill, kept from launch to launch: a tile's
    // fresh vectors cost page faults and zeroing on every tile.
    struct TileOutput {
        cl::Buffer colors, counts;
        std::vector<cl_float4> hostColors;
        std::vector<cl_uint4> hostCounts;
        size_t pixels = 0, rayCounts = 0;  // the entries each holds (TileEntries)
    };
    std::array<TileOutput, kTilesInFlight> outputs;
    // Makes `out` hold a tile's entries, where it holds fewer (sizeTileOutput in the .cpp).
    void sizeTileOutput(TileOutput& out, TileEntries tile);
    // The packet path's block queue (cl/kernel.cl): two counters, zero between launches.
    cl::Buffer blockQueue;
    struct Program {
        KernelProgram program;
        cl::Kernel kernel;
        bool warm = false;  // a tile came back: the launch-time compile is behind it
        // The driver's CL_KERNEL_PRIVATE_MEM_SIZE: private memory a work-item (the GPU
        // budget of docs/performance.md, "The kernel on GPUs"; scripts/gpu_check.sh reports it).
        uint64_t privateBytes = 0;
    };
    std::map<int, Program> programs;  // by frame count (kernelFrames)
    double slowestTileSeconds = 0;    // the slowest tile it has rendered (warm-up tiles aside)
    std::optional<cl::UserEvent> neverSet;  // the test hook hangDevice: what its launches wait for

    ~DeviceSlot();
};

}  // namespace ray::engine
