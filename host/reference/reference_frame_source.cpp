#include "reference/reference_frame_source.h"

#include <chrono>
#include <mutex>
#include <optional>

#include "image/image.h"
#include "reference/reference_renderer.h"
#include "render/device_error.h"

namespace ray {

RenderedFrame ReferenceFrameSource::render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                                           const RenderSettings& settings, const FrameRequest& request) {
    if (request.tiles) throw DeviceError("the reference renderer renders whole frames, not tiles given to it");
    // The reference renderer takes the camera from the scene: a copy of the scene with
    // another camera (the viewer's, the API's), none for the scene's own.
    std::optional<Scene> viewed;
    if (!(camera == scene->camera)) {
        viewed.emplace(*scene);
        viewed->camera = camera;
    }
    ReferenceRenderOptions options;
    options.progress = request.progress;
    options.cancel = request.cancel;
    options.bruteForce = bruteForce_;
    std::mutex oneTileAtATime;  // rows are finished on several threads; onTile is called one at a time
    if (request.onTile)
        options.rowDone = [&](int row, const float* rgb) {
            std::lock_guard lock(oneTileAtATime);
            request.onTile(FinishedTile{{0, row, settings.width, 1}, rgb});
        };
    RayCounts counts;
    RenderedFrame frame;
    const auto start = std::chrono::steady_clock::now();
    Image image = renderReference(viewed ? *viewed : *scene, settings, options, &counts);
    frame.stats.renderSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (request.eightBit)  // rendered as floats: quantized whole at the end
        frame.bytes = quantize8(image);
    else
        frame.image = std::move(image);
    frame.stats.device = bruteForce_ ? "reference (host, no BVH)" : "reference (host)";
    frame.stats.primaryRays = counts.primary;
    frame.stats.shadowRays = counts.shadow;
    frame.stats.secondaryRays = counts.secondary;
    frame.cancelled = request.cancel && request.cancel->load();
    return frame;
}

}  // namespace ray
