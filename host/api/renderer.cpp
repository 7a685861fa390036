// The public Renderer (include/ray/renderer.h) over devices/renderer.h and the OpenCL engine.
#include "ray/renderer.h"

#include <algorithm>

#include "api/camera_conversion.h"
#include "api/error_translation.h"
#include "api/input_checks.h"
#include "api/scene_impl.h"
#include "api/settings_conversion.h"
#include "devices/renderer.h"
#include "image/image.h"
#include "opencl/opencl_device.h"
#include "opencl/opencl_engine.h"

namespace ray::api {

namespace {

// The counts and timings both internal statistics (render/render_stats.h RenderStats, the
// engine's FrameStats) name alike.
template <class InternalStats>
void copyCommonStats(const InternalStats& in, FrameStats& out) {
    out.primaryRays = in.primaryRays;
    out.shadowRays = in.shadowRays;
    out.secondaryRays = in.secondaryRays;
    out.bvhBuildSeconds = in.bvhBuildSeconds;
    out.kernelBuildSeconds = in.kernelBuildSeconds;
    out.renderSeconds = in.renderSeconds;
}

FrameStats external(const ray::RenderOutput& output) {
    FrameStats stats;
    copyCommonStats(output.stats, stats);
    stats.device = output.stats.device;
    stats.cancelled = output.interrupted;
    return stats;
}

}  // namespace

std::vector<Device> listDevices() {
    return detail::translatingErrors([] {
        std::vector<Device> devices;
        for (const ray::OpenClDevice& d : ray::enumerateOpenClDevices())
            devices.push_back({d.index, d.name, d.platformName, d.isGpu, d.isCpu});
        return devices;
    });
}

// Hidden: libray.so exports the public interface only (cmake/libray.map).
struct __attribute__((visibility("hidden"))) Renderer::Impl {
    ray::Scene scene;  // the engine keeps a reference to it: Impl never moves (unique_ptr)
    std::string devices;
    Settings settings;
    std::unique_ptr<ray::OpenClEngine> engine;  // OpenCL selections: made on the first frame

    FrameStats renderOnReference(float* rgb, const ProgressCallback& progress, const std::atomic<bool>* cancel,
                                 const TileCallback& onTile);
    FrameStats renderOnEngine(float* rgb, const ProgressCallback& progress, const std::atomic<bool>* cancel,
                              const TileCallback& onTile);
};

FrameStats Renderer::Impl::renderOnReference(float* rgb, const ProgressCallback& progress,
                                             const std::atomic<bool>* cancel, const TileCallback& onTile) {
    const ray::RenderSettings internalSettings = detail::toInternal(settings);
    ray::RenderJob job{scene, internalSettings, devices, progress};
    job.cancel = cancel;
    ray::RenderOutput output = ray::render(job);
    std::copy(output.image.rgb.begin(), output.image.rgb.end(), rgb);
    if (onTile) onTile({0, 0, output.image.width, output.image.height, rgb});
    return external(output);
}

FrameStats Renderer::Impl::renderOnEngine(float* rgb, const ProgressCallback& progress,
                                          const std::atomic<bool>* cancel, const TileCallback& onTile) {
    if (!engine) engine = std::make_unique<ray::OpenClEngine>(scene, ray::selectOpenClDevices(devices));
    const ray::RenderSettings internalSettings = detail::toInternal(settings);
    ray::FrameOptions options;
    options.progress = progress;
    options.cancel = cancel;  // a cancellable frame has smaller tiles (render/tile_side.h frameTileSide)
    if (onTile)
        options.onTile = [&onTile](const ray::FinishedTile& tile) {
            onTile({tile.rect.x, tile.rect.y, tile.rect.width, tile.rect.height, tile.rgb});
        };
    ray::FrameResult frame = engine->renderFrame(scene.camera, internalSettings, options);
    std::copy(frame.image.rgb.begin(), frame.image.rgb.end(), rgb);
    FrameStats stats;
    for (const ray::DeviceStats& device : frame.stats.devices)
        stats.device += (stats.device.empty() ? "" : ", ") + device.device;
    copyCommonStats(frame.stats, stats);
    stats.packSeconds = frame.stats.packSeconds;
    stats.uploadSeconds = frame.stats.uploadSeconds;
    stats.cancelled = frame.cancelled;
    return stats;
}

Renderer::Renderer(const Scene& scene, const std::string& devices) : impl_(std::make_unique<Impl>()) {
    impl_->scene = scene.impl().scene;
    impl_->devices = devices;
    if (!ray::isDeviceSelection(devices))
        throw InputError("error: the device selection must be auto, cpu, gpu, all, ref or an index from listDevices(), "
                         "not '" + devices + "'", "", 0);
    // The selection is checked now, so that a bad one fails here rather than at the first frame.
    if (!ray::isReferenceDevice(devices)) detail::translatingErrors([&] { ray::selectOpenClDevices(devices); });
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

const std::string& Renderer::devices() const { return impl_->devices; }

void Renderer::setCamera(const Camera& camera) {
    ray::Camera internalCamera = detail::toInternal(camera);
    detail::checkCamera(internalCamera);
    impl_->scene.camera = internalCamera;
}

Camera Renderer::camera() const { return detail::toPublic(impl_->scene.camera); }

void Renderer::setSettings(const Settings& settings) {
    detail::checkSettings(settings);
    impl_->settings = settings;
}

const Settings& Renderer::settings() const { return impl_->settings; }

FrameStats Renderer::render(float* rgb, size_t floatCount, const ProgressCallback& progress,
                            const std::atomic<bool>* cancel, const TileCallback& onTile) {
    const Settings& s = impl_->settings;
    const size_t needed = size_t(s.width) * size_t(s.height) * 3;
    if (rgb == nullptr || floatCount < needed)
        throw InputError("error: the buffer holds " + std::to_string(floatCount) + " floats; a " +
                             std::to_string(s.width) + "x" + std::to_string(s.height) + " frame needs " +
                             std::to_string(needed),
                         "", 0);
    return detail::translatingErrors([&] {
        return ray::isReferenceDevice(impl_->devices) ? impl_->renderOnReference(rgb, progress, cancel, onTile)
                                           : impl_->renderOnEngine(rgb, progress, cancel, onTile);
    });
}

std::vector<float> Renderer::render(FrameStats* stats) {
    std::vector<float> rgb(size_t(impl_->settings.width) * size_t(impl_->settings.height) * 3);
    FrameStats frame = render(rgb.data(), rgb.size());
    if (stats) *stats = frame;
    return rgb;
}

namespace {

// Refuses, before anything is written, pixels that do not make the image or a format
// that cannot be written.
void checkImageToSave(size_t values, int width, int height, const std::filesystem::path& file) {
    if (width <= 0 || height <= 0 || values != size_t(width) * size_t(height) * 3)
        throw InputError("error: an image of " + std::to_string(width) + "x" + std::to_string(height) +
                             " needs width*height*3 values, not " + std::to_string(values),
                         file.string(), 0);
    if (!ray::canWriteImageFormat(file))
        throw InputError("error: cannot write an image in the format of '" + file.string() + "'; " +
                             ray::kOutputFormatAdvice,
                         file.string(), 0);
}

}  // namespace

void saveImage(const std::vector<float>& rgb, int width, int height, const std::filesystem::path& file) {
    checkImageToSave(rgb.size(), width, height, file);
    ray::Image image(width, height);
    image.rgb = rgb;
    detail::translatingErrors([&] { ray::writeImage(image, file); });
}

void saveImage(const std::vector<uint8_t>& rgb, int width, int height, const std::filesystem::path& file) {
    checkImageToSave(rgb.size(), width, height, file);
    if (ray::isFloatFormat(file)) {
        std::vector<float> floats(rgb.size());
        std::transform(rgb.begin(), rgb.end(), floats.begin(), [](uint8_t v) { return float(v) / 255.0f; });
        saveImage(floats, width, height, file);
        return;
    }
    ray::ByteImage image(width, height);
    image.rgb = rgb;
    detail::translatingErrors([&] { ray::writeImage(image, file); });
}

uint8_t toByte(float channel) { return uint8_t(ray::quantize8(channel)); }

const char* version() { return RAY_VERSION; }

}  // namespace ray::api
