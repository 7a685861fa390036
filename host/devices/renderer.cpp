#include "devices/renderer.h"

#include <algorithm>
#include <ostream>

#include "opencl/opencl_frame_source.h"
#include "opencl/opencl_device.h"
#include "reference/reference_frame_source.h"
#include "render/tile_side.h"

namespace ray {

bool isDeviceSelection(const std::string& text) {
    if (text == "auto" || text == "cpu" || text == "gpu" || text == "all" || isReferenceDevice(text)) return true;
    // An index, or a list of them such as 0,2.
    if (text.empty() || text.front() == ',' || text.back() == ',' || text.find(",,") != std::string::npos) return false;
    return std::all_of(text.begin(), text.end(), [](char c) { return c == ',' || (c >= '0' && c <= '9'); });
}

RenderedFrame render(const RenderJob& job) {
    FrameRequest request;
    request.progress = job.progress;
    request.cancel = job.cancel;
    request.tileSize = job.tileSize;  // 0: frameTileSide, smaller when cancellable
    request.eightBit = job.eightBit;
    // Every device of the selection ("all", "0,2") cooperates on the one frame.
    RenderedFrame out = makeFrameSource(job.device, job.referenceBruteForce)
                              ->render(borrowedScene(job.scene), job.scene.camera, job.settings, request);
    // Read again now: a Ctrl-C after the frame's last tile still interrupts the command.
    out.cancelled = out.cancelled || (job.cancel && job.cancel->load());
    out.stats.width = job.settings.width;
    out.stats.height = job.settings.height;
    out.stats.depth = job.settings.maxDepth;
    out.stats.samples = maxSamplesPerPixel(job.settings);
    return out;
}

std::unique_ptr<FrameSource> makeFrameSource(const std::string& device, bool referenceBruteForce) {
    if (isReferenceDevice(device)) return std::make_unique<ReferenceFrameSource>(referenceBruteForce);
    return std::make_unique<OpenClFrameSource>(selectOpenClDevices(device));
}

std::jthread startDeviceEarly(const std::string& device) {
    return isReferenceDevice(device) ? std::jthread() : startOpenClInBackground();
}

void printDeviceList(std::ostream& out) { printOpenClDevices(out); }

int endProcessCleanly(int exitCode) { return endWithoutPoclBuilds(exitCode); }

bool isReferenceDevice(const std::string& device) { return device == "ref" || device == "reference"; }

}  // namespace ray
