#include "devices/renderer.h"

#include <algorithm>
#include <chrono>
#include <ostream>

#include "opencl/opencl_frame_source.h"
#include "opencl/opencl_renderer.h"
#include "reference/reference_frame_source.h"
#include "reference/reference_renderer.h"
#include "render/tile_side.h"

namespace ray {

namespace {

RenderOutput renderOnReference(const RenderJob& job) {
    RenderOutput out;
    ReferenceRenderOptions options;
    options.progress = job.progress;
    options.cancel = job.cancel;
    options.bruteForce = job.referenceBruteForce;
    RayCounts counts;
    auto start = std::chrono::steady_clock::now();
    out.image = renderReference(job.scene, job.settings, options, &counts);
    out.stats.renderSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.stats.device = job.referenceBruteForce ? "reference (host, no BVH)" : "reference (host)";
    out.stats.primaryRays = counts.primary;
    out.stats.shadowRays = counts.shadow;
    out.stats.secondaryRays = counts.secondary;
    return out;
}

}  // namespace

bool isDeviceSelection(const std::string& text) {
    if (text == "auto" || text == "cpu" || text == "gpu" || text == "all" || isReferenceDevice(text)) return true;
    // An index, or a list of them such as 0,2.
    if (text.empty() || text.front() == ',' || text.back() == ',' || text.find(",,") != std::string::npos) return false;
    return std::all_of(text.begin(), text.end(), [](char c) { return c == ',' || (c >= '0' && c <= '9'); });
}

RenderOutput render(const RenderJob& job) {
    RenderOutput out;
    if (isReferenceDevice(job.device)) {
        out = renderOnReference(job);
    } else {
        OpenClRenderOptions options;
        options.progress = job.progress;
        options.cancel = job.cancel;
        options.tileSize = job.tileSize;  // 0: the engine's choice, smaller when cancellable
        // Every device of the selection ("all", "0,2") cooperates on the one frame.
        options.eightBit = job.eightBit;
        FrameResult frame = renderOpenClFrame(selectOpenClDevices(job.device), job.scene, job.settings, options, &out.stats);
        out.image = std::move(frame.image);
        out.bytes = std::move(frame.bytes);
    }
    if (job.eightBit && !out.image.empty()) {  // the reference renders floats
        out.bytes = quantize8(out.image);
        out.image = Image();
    }
    out.interrupted = job.cancel && job.cancel->load();
    out.stats.width = job.settings.width;
    out.stats.height = job.settings.height;
    out.stats.depth = job.settings.maxDepth;
    out.stats.samples = maxSamplesPerPixel(job.settings);
    return out;
}

std::unique_ptr<FrameSource> makeFrameSource(const std::string& device) {
    if (isReferenceDevice(device)) return std::make_unique<ReferenceFrameSource>();
    return std::make_unique<OpenClFrameSource>(selectOpenClDevices(device));
}

std::jthread startDeviceEarly(const std::string& device) {
    return isReferenceDevice(device) ? std::jthread() : startOpenClInBackground();
}

void printDeviceList(std::ostream& out) { printOpenClDevices(out); }

bool isReferenceDevice(const std::string& device) { return device == "ref" || device == "reference"; }

}  // namespace ray
