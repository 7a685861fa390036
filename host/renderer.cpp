#include "renderer.h"

#include <chrono>
#include <ostream>

#include "opencl_renderer.h"
#include "reference_renderer.h"

namespace ray {

namespace {

int maxSamplesPerPixel(const RenderSettings& s) {
    switch (s.antialias) {
        case AntialiasMode::Off: return 1;
        case AntialiasMode::Course: return 64;
        default: return s.samples;
    }
}

RenderOutput renderOnReference(const RenderJob& job) {
    RenderOutput out;
    ReferenceRenderOptions options;
    options.progress = job.progress;
    RayCounts counts;
    auto start = std::chrono::steady_clock::now();
    out.image = renderReference(job.scene, job.settings, options, &counts);
    out.stats.renderSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.stats.device = "reference (host)";
    out.stats.primaryRays = counts.primary;
    out.stats.shadowRays = counts.shadow;
    out.stats.secondaryRays = counts.secondary;
    return out;
}

bool isReference(const std::string& device) { return device == "ref" || device == "reference"; }

}  // namespace

RenderOutput render(const RenderJob& job) {
    RenderOutput out;
    if (isReference(job.device)) {
        out = renderOnReference(job);
    } else {
        std::string devicesUsed;
        for (const OpenClDevice& device : selectOpenClDevices(job.device)) {
            OpenClRenderOptions options;
            options.progress = job.progress;
            out = RenderOutput{};
            out.image = renderOpenCl(device, job.scene, job.settings, options, &out.stats);
            devicesUsed += (devicesUsed.empty() ? "" : ", ") + out.stats.device;
        }
        out.stats.device = devicesUsed;
    }
    out.stats.width = job.settings.width;
    out.stats.height = job.settings.height;
    out.stats.depth = job.settings.maxDepth;
    out.stats.samples = maxSamplesPerPixel(job.settings);
    return out;
}

void printDeviceList(std::ostream& out) { printOpenClDevices(out); }

}  // namespace ray
