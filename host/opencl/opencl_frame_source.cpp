#include "opencl/opencl_frame_source.h"

#include "render/device_error.h"

namespace ray {

namespace {

FrameOptions engineOptions(const FrameRequest& request) {
    FrameOptions options;
    options.tileSize = request.tileSize;
    options.progress = request.progress;
    options.onTile = request.onTile;
    options.cancel = request.cancel;  // a cancellable frame has smaller tiles (render/tile_side.h)
    options.tiles = request.tiles;
    options.eightBit = request.eightBit;
    return options;
}

// The engine's statistics as every caller reads them (render/render_stats.h).
RenderStats renderStatsOf(const FrameStats& frame, const std::vector<OpenClDevice>& devices) {
    RenderStats stats;
    for (const OpenClDevice& d : devices) stats.device += (stats.device.empty() ? "" : ", ") + d.description();
    stats.primaryRays = frame.primaryRays;
    stats.shadowRays = frame.shadowRays;
    stats.secondaryRays = frame.secondaryRays;
    stats.packSeconds = frame.packSeconds;
    stats.bvhBuildSeconds = frame.bvhBuildSeconds;
    stats.kernelBuildSeconds = frame.kernelBuildSeconds;
    stats.uploadSeconds = frame.uploadSeconds;
    stats.renderSeconds = frame.renderSeconds;
    stats.devices = frame.devices;
    stats.warnings = frame.warnings;
    return stats;
}

}  // namespace

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
    FrameResult result = engine_->renderFrame(camera, settings, engineOptions(request));
    RenderedFrame frame;
    frame.image = std::move(result.image);
    frame.bytes = std::move(result.bytes);
    frame.stats = renderStatsOf(result.stats, devices_);
    frame.cancelled = result.cancelled;
    return frame;
}

std::string OpenClFrameSource::deviceName() const {
    std::string names;
    for (const OpenClDevice& device : devices_) names += (names.empty() ? "" : ", ") + device.name;
    return names;
}

}  // namespace ray
