#include "render/tile_side.h"

#include <algorithm>
#include <cmath>

namespace ray {

namespace {

// A cancellable render's tiles hold at most this many samples (pixels x samples per
// pixel): the tiles already queued must finish before it stops. Measured on PoCL (2 busy
// cores, chess.xml 1024x768, depth 8, SIGINT to exit): 64x64 tiles at 4096 samples took
// 8.5 s; with 64^3 samples a tile, 0.3-0.6 s at 64 and 4096 samples but 1.2 s at 256;
// hence half that. chess.xml's samples trace about 2.5 rays each (a camera ray and the
// shadow rays of its two point lights where it hits).
constexpr double kCancellableTileSamples = 64 * 64 * 32;
constexpr double kCalibrationRaysPerSample = 2.5;

}  // namespace

int maxSamplesPerPixel(const RenderSettings& s) {
    switch (s.antialias) {
        case AntialiasMode::Off: return 1;
        case AntialiasMode::Course: return 64;
        default: return s.samples;
    }
}

int cancellableTileSize(const RenderSettings& settings, const Scene& scene) {
    // A sample that meets an area light traces k² shadow rays for it: count the samples by
    // the rays they trace when that is more than the calibration scene's.
    const int side = areaLightGridSide(settings);
    double raysPerSample = 1;
    for (const Light& light : scene.lights) raysPerSample += light.type == LightType::Area ? side * side : 1;
    double weight = std::max(1.0, raysPerSample / kCalibrationRaysPerSample);
    int tileSide = int(std::sqrt(kCancellableTileSamples / (maxSamplesPerPixel(settings) * weight)));
    // No larger than an uncancellable frame's: at one sample a pixel the budget allows 360
    // pixels, and 64 (the cap until 2026-12-05) cost PoCL four times the launches of 128,
    // each a hand-over between its threads (recursiveCones4 2048x1536: 0.429 -> 0.394 s).
    return std::clamp(tileSide / 8 * 8, 8, kDefaultTileSide);
}

int frameTileSide(const RenderSettings& settings, const Scene& scene, bool cancellable, int requested) {
    if (requested > 0) return std::max(8, requested);
    return cancellable ? cancellableTileSize(settings, scene) : kDefaultTileSide;
}

}  // namespace ray
