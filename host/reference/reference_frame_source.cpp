#include "reference/reference_frame_source.h"

#include "image/image.h"
#include "reference/reference_renderer.h"

namespace ray {

uint64_t ReferenceFrameSource::renderFrame(const std::shared_ptr<const Scene>& scene, const Camera& camera, const RenderSettings& settings,
                                           const std::function<void(const FrameTile&)>& onTile,
                                           const std::atomic<bool>& cancel) {
    // The reference renderer takes the camera from the scene: a copy with the viewer's.
    // (It builds its BVH per frame too; OpenClFrameSource's engine does not.)
    Scene viewed = *scene;
    viewed.camera = camera;
    ReferenceRenderOptions options;
    options.cancel = &cancel;
    options.rowDone = [&](int row, const float* rgb) {
        onTile(FrameTile{0, row, settings.width, 1, quantize8(rgb, size_t(settings.width) * 3)});
    };
    RayCounts counts;
    renderReference(viewed, settings, options, &counts);
    return counts.total();
}

}  // namespace ray
