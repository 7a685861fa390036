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
#include "image/image_write.h"
#include "opencl/opencl_device.h"
#include "reference/reference_bvh.h"
#include "reference/reference_renderer.h"

namespace ray::api {

namespace {

FrameStats external(const ray::RenderedFrame& frame) {
    FrameStats stats;
    const ray::RenderStats& in = frame.stats;
    // OpenCL devices by index and name, as listDevices() numbers them; the reference by name.
    for (const ray::DeviceStats& device : in.devices)
        stats.device += (stats.device.empty() ? "" : ", ") + device.device;
    if (in.devices.empty()) stats.device = in.device;
    stats.primaryRays = in.primaryRays;
    stats.shadowRays = in.shadowRays;
    stats.secondaryRays = in.secondaryRays;
    stats.bvhBuildSeconds = in.bvhBuildSeconds;
    stats.kernelBuildSeconds = in.kernelBuildSeconds;
    stats.renderSeconds = in.renderSeconds;
    stats.packSeconds = in.packSeconds;
    stats.uploadSeconds = in.uploadSeconds;
    stats.sceneUpdate = {in.sceneUpdate.packing, in.sceneUpdate.bvh, in.sceneUpdate.tables};
    stats.cancelled = frame.cancelled;
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
    std::shared_ptr<Scene> scene;  // the caller's to edit (Renderer::scene)
    // What frames render: the scene's flattened form, shared with the frame source, which
    // keeps what it prepared for it (the packed scene on OpenCL devices) from frame to
    // frame. Taken again when the scene was edited (frameScene()); the frame source then
    // prepares only what the edit said it changed (the scene's lineage).
    std::shared_ptr<const ray::Scene> rendered;
    // pick's search structure, over `picked` (rebuilt after an edit).
    std::shared_ptr<const ray::Scene> picked;
    std::unique_ptr<ray::reference::SceneIntersector> picker;
    std::string devices;
    Settings settings;
    std::unique_ptr<ray::FrameSource> frames;  // devices/renderer.h makeFrameSource

    // The flattened scene as it is now: the same object as long as the scene renders as
    // it did when last taken (a change of its camera alone keeps its revision: each frame
    // takes the camera itself).
    const std::shared_ptr<const ray::Scene>& frameScene() {
        std::shared_ptr<const ray::Scene> now = scene->impl().flattened();
        if (!rendered || rendered->lineage.revision != now->lineage.revision) rendered = std::move(now);
        return rendered;
    }
};

Renderer::Renderer(const Scene& scene, const std::string& devices) : Renderer(std::make_shared<Scene>(scene), devices) {}

Renderer::Renderer(std::shared_ptr<Scene> scene, const std::string& devices) : impl_(std::make_unique<Impl>()) {
    if (!scene) throw InputError("error: the renderer's scene is null", "", 0);
    impl_->scene = std::move(scene);
    impl_->devices = devices;
    if (!ray::isDeviceSelection(devices))
        throw InputError("error: the device selection must be auto, cpu, gpu, all, ref or an index from listDevices(), "
                         "not '" + devices + "'", "", 0);
    // The devices are selected now, so that a bad selection fails here rather than at the
    // first frame; nothing is packed or built before it.
    impl_->frames = detail::translatingErrors([&] { return ray::makeFrameSource(devices); });
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

const std::string& Renderer::devices() const { return impl_->devices; }

Scene& Renderer::scene() { return *impl_->scene; }
const Scene& Renderer::scene() const { return *impl_->scene; }

void Renderer::setCamera(const Camera& camera) { impl_->scene->setCamera(camera); }

Camera Renderer::camera() const { return impl_->scene->camera(); }

std::optional<Pick> Renderer::pick(int x, int y) {
    const Settings& s = impl_->settings;
    if (x < 0 || y < 0 || x >= s.width || y >= s.height)
        throw InputError("error: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                             std::to_string(s.width) + "x" + std::to_string(s.height) + " image",
                         "", 0);
    return detail::translatingErrors([&]() -> std::optional<Pick> {
        const std::shared_ptr<const ray::Scene>& scene = impl_->frameScene();
        if (impl_->picked != scene) {
            impl_->picker.reset();
            impl_->picked = scene;
            impl_->picker = std::make_unique<ray::reference::SceneIntersector>(*scene);
        }
        const ray::RenderSettings settings = detail::toInternal(s);
        const auto hit = ray::pickPixel(*scene, *impl_->picker, impl_->scene->impl().document().camera, settings, x, y);
        if (!hit) return std::nullopt;
        Pick pick;
        pick.instance = size_t(hit->primitive);
        pick.object = (*scene).primitives[size_t(hit->primitive)].sourceObject;
        pick.point = {hit->point.x, hit->point.y, hit->point.z};
        pick.normal = {hit->normal.x, hit->normal.y, hit->normal.z};
        pick.distance = hit->distance;
        return pick;
    });
}

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
    ray::FrameRequest request;
    request.progress = progress;
    request.cancel = cancel;  // a cancellable frame has smaller tiles (render/tile_side.h frameTileSide)
    if (onTile)
        request.onTile = [&onTile](const ray::FinishedTile& tile) {
            onTile({tile.rect.x, tile.rect.y, tile.rect.width, tile.rect.height, tile.rgb});
        };
    return detail::translatingErrors([&] {
        const ray::RenderedFrame frame = impl_->frames->render(
            impl_->frameScene(), impl_->scene->impl().document().camera, detail::toInternal(impl_->settings), request);
        std::copy(frame.image.rgb.begin(), frame.image.rgb.end(), rgb);
        return external(frame);
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
    detail::checkImageToSaveSize(width, height, file.string());
    if (values != size_t(width) * size_t(height) * 3)
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
    saveImage(rgb, width, height, file, WriteOptions{});
}

void saveImage(const std::vector<float>& rgb, int width, int height, const std::filesystem::path& file,
               const WriteOptions& options) {
    checkImageToSave(rgb.size(), width, height, file);
    ray::Image image(width, height);
    image.rgb = rgb;
    detail::translatingErrors([&] { ray::writeImage(image, file, detail::writeOptionsOf(options)); });
}

void saveImage(const std::vector<uint8_t>& rgb, int width, int height, const std::filesystem::path& file) {
    saveImage(rgb, width, height, file, WriteOptions{});
}

void saveImage(const std::vector<uint8_t>& rgb, int width, int height, const std::filesystem::path& file,
               const WriteOptions& options) {
    checkImageToSave(rgb.size(), width, height, file);
    if (ray::isFloatFormat(file)) {
        std::vector<float> floats(rgb.size());
        std::transform(rgb.begin(), rgb.end(), floats.begin(), [](uint8_t v) { return float(v) / 255.0f; });
        saveImage(floats, width, height, file, options);
        return;
    }
    ray::ByteImage image(width, height);
    image.rgb = rgb;
    detail::translatingErrors([&] { ray::writeImage(image, file, detail::writeOptionsOf(options)); });
}

uint8_t toByte(float channel) { return uint8_t(ray::quantize8(channel)); }

const char* version() { return RAY_VERSION; }

}  // namespace ray::api
