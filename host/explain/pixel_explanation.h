// "Explain this pixel": the tree of rays of one pixel, as the reference renderer traced it.
//
// explainPixel runs the reference renderer on one pixel with a TraceObserver that records
// every ray, hit, lighting term and stopped branch (reference/trace_observer.h). Nothing
// here computes a color: the tree only holds what the renderer reported, so its colors
// are the reference's by construction.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "reference/trace_observer.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace ray {

struct ExplainedStop {
    TraceRayKind kind;
    BranchStop reason;
};

struct ExplainedRay {
    TraceRayKind kind = TraceRayKind::Camera;
    Vec3 origin, direction;
    int depth = 0;
    Vec3 weight{1, 1, 1};  // accumulated weight of this ray on its way to the camera
    Vec3 factor{1, 1, 1};  // ks·Or or kt·Ot: what the parent multiplies the clamped color by
    bool hit = false;      // false: nothing hit, the background (black) is seen
    TraceHitInfo hitInfo;
    Vec3 ambient, emissive, diffuseColor, texel;
    bool textured = false;
    std::vector<TraceLightTerm> lights;
    std::vector<ExplainedStop> stops;  // branches not traced, and why
    std::vector<std::unique_ptr<ExplainedRay>> children;
    Vec3 color;  // this ray's color before its parent clamps it
};

struct ExplainedSample {
    int index = 0;
    double sx = 0.5, sy = 0.5, time = 0;
    Vec3 color;  // as the camera ray returned it (the sampling pattern clamps it where it says)
    std::unique_ptr<ExplainedRay> ray;
    // The course's depth of field (SPEC §3): the sample is the mean of the clamped colors of
    // 25 lens rays, ray and these 24 others.
    std::vector<std::unique_ptr<ExplainedRay>> otherLensRays;
};

struct PixelExplanation {
    int x = 0, y = 0;
    RenderSettings settings;
    std::vector<ExplainedSample> samples;
    Vec3 color;      // the pixel as the reference image holds it (float), before clamping
    Vec3 clamped;    // clamped to [0, 1]
    std::array<int, 3> bytes{};  // floor(255·clamped), what an 8-bit file holds (SPEC §4)
};

// Traces pixel (x, y) with the reference renderer. Throws std::out_of_range for a pixel
// outside the image.
PixelExplanation explainPixel(const Scene& scene, const RenderSettings& settings, int x, int y);

// "scene.xml:12" for a primitive of the scene.
std::string primitiveSource(const Scene& scene, int primitive);

}  // namespace ray
