#include "render/frame_source.h"

namespace ray {

RenderStats FrameSource::renderFrame(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                                  const RenderSettings& settings,
                                  const std::function<void(const FrameTile&)>& onTile,
                                  const std::atomic<bool>& cancel) {
    FrameRequest request;
    request.cancel = &cancel;  // also makes the tiles small: the first one comes soon
    request.onTile = [&](const FinishedTile& tile) {
        const TileRect& r = tile.rect;
        onTile(FrameTile{r.x, r.y, r.width, r.height, quantize8(tile.rgb, r.pixels() * 3)});
    };
    return render(scene, camera, settings, request).stats;
}

std::shared_ptr<const Scene> borrowedScene(const Scene& scene) {
    // The aliasing constructor with an empty owner: a pointer that shares nothing.
    return std::shared_ptr<const Scene>(std::shared_ptr<const Scene>(), &scene);
}

}  // namespace ray
