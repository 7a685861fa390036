#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>

#include "opencl/opencl_renderer.h"
#include "reference/reference_renderer.h"

namespace ray {

int maxSamplesPerPixel(const RenderSettings& s) {
    switch (s.antialias) {
        case AntialiasMode::Off: return 1;
        case AntialiasMode::Course: return 64;
        default: return s.samples;
    }
}

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

// A cancellable render's tiles hold at most this many samples (pixels x samples per
// pixel): the tiles already queued must finish before it stops. Measured on PoCL (2 busy
// cores, chess.xml 1024x768, depth 8, SIGINT to exit): 64x64 tiles at 4096 samples took
// 8.5 s; with 64^3 samples a tile, 0.3-0.6 s at 64 and 4096 samples but 1.2 s at 256;
// hence half that. chess.xml's samples trace about 2.5 rays each (a camera ray and the
// shadow rays of its two point lights where it hits).
constexpr double kCancellableTileSamples = 64 * 64 * 32;
constexpr double kCalibrationRaysPerSample = 2.5;

}  // namespace

int cancellableTileSize(const RenderSettings& settings, const Scene& scene) {
    // A sample that meets an area light traces k² shadow rays for it: count the samples by
    // the rays they trace when that is more than the calibration scene's.
    const int side = areaLightGridSide(settings);
    double raysPerSample = 1;
    for (const Light& light : scene.lights) raysPerSample += light.type == LightType::Area ? side * side : 1;
    double weight = std::max(1.0, raysPerSample / kCalibrationRaysPerSample);
    int tileSide = int(std::sqrt(kCancellableTileSamples / (maxSamplesPerPixel(settings) * weight)));
    return std::clamp(tileSide / 8 * 8, 8, 64);
}

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
        // A cancellable render uses smaller tiles: the tiles already queued must finish
        // before it stops, and at 128x128 with many samples that can take seconds.
        if (job.cancel) options.tileSize = cancellableTileSize(job.settings, job.scene);
        if (job.tileSize > 0) options.tileSize = job.tileSize;
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

std::jthread startDeviceEarly(const std::string& device) {
    return isReferenceDevice(device) ? std::jthread() : startOpenClInBackground();
}

void printDeviceList(std::ostream& out) { printOpenClDevices(out); }

bool isReferenceDevice(const std::string& device) { return device == "ref" || device == "reference"; }

}  // namespace ray
