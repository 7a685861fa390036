#include "opencl/opencl_frame_source.h"

#include "image/image.h"
#include "render/device_error.h"

namespace ray {

OpenClFrameSource::OpenClFrameSource(std::vector<OpenClDevice> devices) : devices_(std::move(devices)) {
    if (devices_.empty()) throw DeviceError("no OpenCL device selected; try --device ref");
}

OpenClFrameSource::~OpenClFrameSource() = default;

uint64_t OpenClFrameSource::renderFrame(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                                        const RenderSettings& settings,
                                        const std::function<void(const FrameTile&)>& onTile,
                                        const std::atomic<bool>& cancel) {
    // A new scene (the file was saved) is packed and uploaded once; every other frame, a
    // camera or settings change, reuses what the engine holds. The scene is kept alive
    // here as long as the engine refers to it.
    if (scene != scene_) {
        engine_.reset();
        scene_ = scene;
        engine_ = std::make_unique<OpenClEngine>(*scene_, devices_);
    }
    FrameOptions options;
    options.cancel = &cancel;  // also makes the tiles small: the first one comes soon
    options.onTile = [&](const FinishedTile& finished) {
        const size_t samples = size_t(finished.rect.width) * size_t(finished.rect.height) * 3;
        onTile(FrameTile{finished.rect.x, finished.rect.y, finished.rect.width, finished.rect.height,
                         quantize8(finished.rgb, samples)});
    };
    const FrameResult result = engine_->renderFrame(camera, settings, options);
    return result.stats.primaryRays + result.stats.shadowRays + result.stats.secondaryRays;
}

std::string OpenClFrameSource::deviceName() const {
    std::string names;
    for (const OpenClDevice& device : devices_) names += (names.empty() ? "" : ", ") + device.name;
    return names;
}

}  // namespace ray
