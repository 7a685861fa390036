#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
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

// A cancellable render's tiles hold at most this many samples (pixels x samples per
// pixel): the tiles already queued must finish before it stops. Measured on PoCL (2 busy
// cores, chess.xml 1024x768, depth 8, SIGINT to exit): 64x64 tiles at 4096 samples took
// 8.5 s; with 64^3 samples a tile, 0.3-0.6 s at 64 and 4096 samples but 1.2 s at 256;
// hence half that.
constexpr double kCancellableTileSamples = 64 * 64 * 32;

// The side of such a tile, a multiple of the 8x8 work-group: 64 up to 32 samples a pixel,
// 40 for the course's 64, down to 8 for 4096.
int cancellableTileSize(const RenderSettings& settings) {
    int side = int(std::sqrt(kCancellableTileSamples / maxSamplesPerPixel(settings)));
    return std::clamp(side / 8 * 8, 8, 64);
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
            options.cancel = job.cancel;
            // A cancellable render uses smaller tiles: the tiles already queued must finish
            // before it stops, and at 128x128 with many samples that can take seconds.
            if (job.cancel) options.tileSize = cancellableTileSize(job.settings);
            out = RenderOutput{};
            out.image = renderOpenCl(device, job.scene, job.settings, options, &out.stats);
            devicesUsed += (devicesUsed.empty() ? "" : ", ") + out.stats.device;
        }
        out.stats.device = devicesUsed;
    }
    out.interrupted = job.cancel && job.cancel->load();
    out.stats.width = job.settings.width;
    out.stats.height = job.settings.height;
    out.stats.depth = job.settings.maxDepth;
    out.stats.samples = maxSamplesPerPixel(job.settings);
    return out;
}

void printDeviceList(std::ostream& out) { printOpenClDevices(out); }

}  // namespace ray
