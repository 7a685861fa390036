#include "opencl/opencl_frame_source.h"

#include "render/device_error.h"

namespace ray {

OpenClFrameSource::OpenClFrameSource(std::vector<OpenClDevice> devices) : devices_(std::move(devices)) {
    if (devices_.empty()) throw DeviceError("no OpenCL device selected; try --device ref");
}

OpenClFrameSource::~OpenClFrameSource() = default;

RenderedFrame OpenClFrameSource::render(const std::shared_ptr<const Scene>& scene, const Camera& camera,
                                        const RenderSettings& settings, const FrameRequest& request) {
    // A new scene (the file was saved, or an editor's edit) is handed to the engine, which
    // packs and uploads what differs from the scene it holds (opencl_engine.h setScene);
    // every other frame, a camera or settings change, reuses what the engine holds. The
    // engine shares the scene, so it outlives nothing it refers to.
    if (!engine_) {
        engine_ = std::make_unique<OpenClEngine>(scene, devices_);
    } else if (scene != scene_) {
        engine_->setScene(scene);
    }
    scene_ = scene;
    return engine_->renderFrame(camera, settings, request);
}

std::string OpenClFrameSource::deviceName() const {
    std::string names;
    for (const OpenClDevice& device : devices_) names += (names.empty() ? "" : ", ") + device.name;
    return names;
}

}  // namespace ray
