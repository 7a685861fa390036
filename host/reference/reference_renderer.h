// The host reference renderer: the oracle the OpenCL kernel is tested against.
//
// Plain and recursive, in double precision, following SPEC §3-§5 line by line. It is
// not the fast path; clarity wins over speed everywhere in it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>

#include "image/image.h"
#include "render/render_settings.h"
#include "scene/scene.h"
#include "reference/reference_bvh.h"
#include "reference/trace_observer.h"

namespace ray {

struct RayCounts {
    uint64_t primary = 0, shadow = 0, secondary = 0;
    uint64_t total() const { return primary + shadow + secondary; }
};

struct ReferenceRenderOptions {
    int threads = 0;  // 0: all hardware threads
    // Called now and then with the fraction of rows done (from any thread).
    std::function<void(double)> progress;
    // Set to true to stop early; rows not yet rendered stay black.
    const std::atomic<bool>* cancel = nullptr;
    // Called (from the thread that rendered it) with each finished row and its pixels
    // (width × 3 floats), so that a viewer can show the image as it grows.
    std::function<void(int row, const float* rgb)> rowDone;
    // Test every primitive for every ray instead of searching the BVH: slow; a test checks
    // that the BVH changes nothing, and the bench times the kernel against it (--no-bvh).
    bool bruteForce = false;
};

// Throws InputError when the scene uses something this renderer cannot draw yet.
Image renderReference(const Scene& scene, const RenderSettings& settings,
                      const ReferenceRenderOptions& options = {}, RayCounts* counts = nullptr);

// The color of one pixel (x, y) of the image renderReference would make with these
// settings (before clamping; the image holds it as float), traced on the calling thread,
// every step reported to `observer` (may be null). Throws std::out_of_range for a pixel
// outside the image.
Vec3 renderReferencePixel(const Scene& scene, const RenderSettings& settings, int x, int y, TraceObserver* observer,
                          const ReferenceRenderOptions& options = {}, RayCounts* counts = nullptr);

// What the camera ray through the centre of pixel (x, y) of a settings.width ×
// settings.height image meets first: picking an object on screen. The ray is the pinhole
// ray (a lens's centre), at shutter time 0, found in double precision on the host, so the
// answer does not depend on the device that renders the image. Nothing: the background.
struct PickedSurface {
    int primitive = -1;   // index into Scene::primitives
    int csgOperand = -1;  // a csg object's hit: the operand whose surface it is
    Vec3 point;           // the hit point (world space)
    Vec3 normal;          // the surface's outward unit normal there (world space)
    double distance = 0;  // from the eye to the point
};
// intersector: over `scene` (made once by a caller that picks often). Throws
// std::out_of_range for a pixel outside the image.
std::optional<PickedSurface> pickPixel(const Scene& scene, const reference::SceneIntersector& intersector,
                                       const Camera& camera, const RenderSettings& settings, int x, int y);

}  // namespace ray
