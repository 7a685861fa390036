#include "opencl/device_thread.h"

#include <algorithm>
#include <exception>

#include "opencl/device_worker.h"
#include "opencl/engine_frame.h"
#include "opencl/kernel_arguments.h"
#include "opencl/kernel_build.h"
#include "opencl/scene_upload.h"
#include "render/device_error.h"

namespace ray::engine {

namespace {

DeviceError describeClError(const OpenClDevice& device, const cl::Error& e) {
    std::string what = openClErrorName(e.err());
    std::string advice = (e.err() == CL_MEM_OBJECT_ALLOCATION_FAILURE || e.err() == CL_OUT_OF_RESOURCES ||
                          e.err() == CL_OUT_OF_HOST_MEMORY)
                             ? "the device ran out of memory; try a smaller image or scene, or --device ref"
                             : "try another device (ray --list-devices) or --device ref";
    return DeviceError(device.description() + ": " + e.what() + " failed with " + what + "; " + advice);
}

// The device's context and queue (and on the packet path its block queue), on its first frame.
void openDevice(DeviceSlot& slot) {
    slot.context = cl::Context(slot.device.device);
    slot.queue = cl::CommandQueue(slot.context, slot.device.device);
    if (slot.variant.lanes > 1) {
        cl_uint empty[2] = {0, 0};
        slot.blockQueue = cl::Buffer(slot.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof(empty), empty);
    }
}

// Uploads the scene (when the device holds another packing), sizes the output buffers,
// builds (or reuses) the program for the frame's depth bucket (kernelFrames) and binds the buffers. Reports the
// seconds spent uploading and building to the frame.
cl::Kernel& prepareDevice(DeviceSlot& slot, Frame& frame) {
    if (slot.uploaded != frame.packed || slot.checkedTilePixels != frame.tilePixels()) {
        checkDeviceLimits(slot.device, slot.variant, *frame.packed, frame.tilePixels() * sizeof(cl_float4));
        slot.checkedTilePixels = frame.tilePixels();
    }
    if (!slot.context()) openDevice(slot);
    double uploadSeconds = 0, buildSeconds = 0;
    auto start = Clock::now();
    if (slot.uploaded != frame.packed && uploadScene(slot, frame.packed)) uploadSeconds = secondsSince(start);
    const int frames = kernelFrames(frame.settings.maxDepth);
    auto found = slot.programs.find(frames);
    if (found == slot.programs.end()) {
        start = Clock::now();
        DeviceSlot::Program program = buildDeviceProgram(slot, frames, frame.params);
        buildSeconds = secondsSince(start);
        found = slot.programs.emplace(frames, std::move(program)).first;
    }
    cl::Kernel& kernel = found->second.kernel;
    // The scene's buffers and the block queue; the launch parameters and the tile outputs are
    // set at each launch.
    for (size_t i = 0; i < kSceneBufferCount; ++i)
        kernel.setArg(kernel_argument::kFirstSceneBuffer + cl_uint(i), slot.sceneBuffers[i]);
    if (slot.variant.lanes > 1) kernel.setArg(kernel_argument::kBlockQueue, slot.blockQueue);
    for (DeviceSlot::TileOutput& out : slot.outputs)
        slot.sizeTileOutput(out, tileEntries(frame.tileWidth, frame.tileHeight, slot.variant.lanes));
    slot.queue.finish();
    std::lock_guard lock(frame.mutex);
    frame.uploadSeconds = std::max(frame.uploadSeconds, uploadSeconds);
    frame.buildSeconds = std::max(frame.buildSeconds, buildSeconds);
    return kernel;
}

// Under the frame's lock, once the device is prepared: it renders, unless the frame was done
// without it (its program is kept for the next frame) or cancelled.
bool startRendering(DeviceSlot& slot, Frame& frame) {
    Frame::Participant& p = frame.devices[size_t(slot.index)];
    if (frame.closed || p.part != Frame::Part::Preparing) return false;
    const Clock::time_point now = Clock::now();
    p.part = Frame::Part::Rendering;
    if (!frame.renderingSince) frame.renderingSince = now;
    p.warm = slot.programs.at(kernelFrames(frame.settings.maxDepth)).warm;
    p.slowestTileSeconds = slot.slowestTileSeconds;
    p.lastAnswer = now;
    return true;
}

// The device's part in one frame: prepare, then render if the frame still wants it. A
// failure drops the device, its tiles going to the others.
void serveFrame(DeviceSlot& slot, Frame& frame) {
    try {
        try {
            {
                std::lock_guard lock(frame.mutex);
                if (frame.closed) return;  // the device was busy until the frame was over
            }
            cl::Kernel& kernel = prepareDevice(slot, frame);
            {
                std::lock_guard lock(frame.mutex);
                if (!startRendering(slot, frame)) return;
            }
            renderTiles(frame, slot, kernel);
        } catch (const cl::Error& err) {
            throw describeClError(slot.device, err);
        }
    } catch (const std::exception& err) {
        {
            std::lock_guard lock(slot.mutex);
            slot.dropped = true;
            slot.failure = err.what();
        }
        std::lock_guard lock(frame.mutex);
        frame.deviceFailed(slot.index);
    }
}

}  // namespace

void serveFrames(std::shared_ptr<DeviceSlot> slot) {
    uint64_t served = 0;
    while (true) {
        std::shared_ptr<Frame> frame;
        {
            std::unique_lock lock(slot->mutex);
            slot->busy = false;
            slot->wake.wait(lock, [&] { return slot->stop || slot->dropped || slot->frameNumber != served; });
            if (slot->stop || slot->dropped) return;
            frame = slot->frame;
            served = slot->frameNumber;
            slot->busy = true;
        }
        if (frame) serveFrame(*slot, *frame);
    }
}

}  // namespace ray::engine
