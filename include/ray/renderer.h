/// \file
/// Rendering a Scene with ray's public API: choose devices once, render many frames.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ray/errors.h"
#include "ray/scene.h"

namespace ray::api {

/// How a pixel is sampled (`--aa`): one ray through its centre, the course's adaptive
/// subdivision, a jittered grid of Settings::samples, or 2×2 jittered samples refined where
/// they differ.
enum class Antialias { Off, Course, Stratified, Adaptive };
/// How textures are read (`--texture-filter`): the nearest texel, the four nearest, or
/// mipmaps; Course: bilinear with texel corners at integer coordinates, as the course's renders.
enum class TextureFilter { Nearest, Bilinear, Trilinear, Course };
/// Depth of field (docs/conventions.md, "Beyond the course"): Course, the course's 5×5 lens
/// grid (SPEC §3); Disk, one random point of the lens disk a sample.
enum class DofMode { Course, Disk };

/// What to render: the same switches as the command line (see docs/user-guide.md, "Using it");
/// each is also settable by name (setSetting), as `ray --help` and describeSettings() list them.
struct Settings {
    ///@{
    /// The image's size in pixels (1..16384 each).
    int width = 1024, height = 768;
    ///@}
    int depth = 4;                          ///< bounces after the camera ray
    Antialias antialias = Antialias::Course;  ///< how pixels are sampled (`--aa`)
    int samples = 16;                       ///< Stratified / Adaptive
    uint32_t seed = 0;                      ///< picks another deterministic noise pattern (`--seed`)
    int areaSamples = 16;                   ///< point samples an area light is cut into (`--area-samples`)
    double shutter = 1;                     ///< motion blur: fraction of the motion
    double threshold = 1.0 / 256.0;         ///< weight below which a branch stops
    ///@{
    /// A feature switch; false is the command line's `--no-shadows`, `--no-reflections`, ...
    bool shadows = true, reflections = true, refraction = true, textures = true, depthOfField = true;
    ///@}
    DofMode dofMode = DofMode::Course;      ///< --dof: how a camera with an aperture samples its lens
    bool fresnel = false;                   ///< --fresnel: exact Fresnel weights on transparent surfaces
    bool courseMeshes = false;              ///< --course-meshes: mesh hits as the course's renderer finds them
    TextureFilter textureFilter = TextureFilter::Nearest;  ///< `--texture-filter`
};

/// A setting by name, for front ends that take settings as text or dynamic values (the
/// Python module's keywords): the name is the command line's option with underscores
/// ("course_meshes" for --course-meshes and Settings::courseMeshes; "dof" for depth of
/// field on or off, "dof_mode" for --dof).
struct SettingDescription {
    /// What values the setting takes: a whole number, a number, on/off, or one of named choices.
    enum class Kind { Integer, Number, Switch, Choice };
    std::string name;                  ///< the keyword: the command line's option with underscores
    Kind kind = Kind::Switch;          ///< what values it takes
    ///@{
    /// The range of an Integer or Number setting, both ends included.
    double minimum = 0, maximum = 0;
    ///@}
    std::vector<std::string> choices;  ///< a Choice's names, in the order of the enum's values
    std::string help;                  ///< a phrase, as `ray --help` shows it
};

/// Every setting of Settings, in the order `ray --help` lists them.
std::vector<SettingDescription> describeSettings();

/// A setting's value: Integer int64_t, Number double (or int64_t), Switch bool, Choice its name.
using SettingValue = std::variant<bool, int64_t, double, std::string>;

/// Sets the setting `name` in `settings`. Throws InputError for an unknown name, a value of
/// another kind, a value out of range or a name that is not one of the choices.
void setSetting(Settings& settings, const std::string& name, const SettingValue& value);

/// An OpenCL device, as `ray --list-devices` numbers them.
struct Device {
    int index = 0;                          ///< its number, for a device selection ("2", "0,2")
    ///@{
    /// The device's and its platform's names, as the driver gives them.
    std::string name, platform;
    ///@}
    ///@{
    /// Whether the device is a GPU, a CPU.
    bool gpu = false, cpu = false;
    ///@}
};

/// Every OpenCL device of every platform (empty without an OpenCL platform).
std::vector<Device> listDevices();

/// What one frame did.
struct FrameStats {
    std::string device;                     ///< the device(s) used
    ///@{
    /// The rays traced: from the camera, towards lights, reflected and refracted.
    uint64_t primaryRays = 0, shadowRays = 0, secondaryRays = 0;
    ///@}
    double packSeconds = 0;                 ///< packing the scene (0 when an earlier frame's is kept)
    double bvhBuildSeconds = 0;             ///< building the BVH (part of packing)
    double uploadSeconds = 0;               ///< uploading it to the devices (0 when kept)
    double kernelBuildSeconds = 0;          ///< compiling (or loading the cached) kernel
    double renderSeconds = 0;               ///< rendering the frame
    bool cancelled = false;                 ///< stopped early: unrendered pixels are black
    /// How the frame got the scene's tables after the latest edits (OpenCL devices).
    struct SceneUpdate {
        /// "none": an earlier frame's kept (or no tables: the host renderer); "edit": re-packed
        /// as the edits said; "compared": re-packed after comparing scenes; "full": packed whole.
        std::string packing = "none";
        std::string bvh = "kept";         ///< "kept", "refit" or "rebuilt"
        std::vector<std::string> tables;  ///< the tables re-packed, which every device uploads again
    };
    SceneUpdate sceneUpdate;  ///< what this frame re-packed and re-uploaded
};

/// What a pixel shows (Renderer::pick): the surface its camera ray meets first.
struct Pick {
    size_t instance = 0;    ///< the primitive instance hit: its index among the scene's primitives (flattened)
    /// The stable id of the scene's object (the scenefile's `<object type="primitive">`, or
    /// one placed with addPrimitive) that instance comes from: Scene::objectOfInstance.
    int object = -1;
    Vec3 point;             ///< the hit point (world space)
    Vec3 normal;            ///< the surface's outward unit normal there (world space)
    double distance = 0;    ///< from the eye to the point
};

/// Called now and then with the fraction of the frame done, from a worker thread.
using ProgressCallback = std::function<void(double fraction)>;

/// A finished tile: its rectangle and its pixels (width × height RGB floats, row by row).
struct Tile {
    ///@{
    /// The tile's rectangle in the frame: its top-left pixel and its size.
    int x = 0, y = 0, width = 0, height = 0;
    ///@}
    const float* rgb = nullptr;             ///< its pixels; the pointer is valid during the callback only
};
/// Called once for each finished tile, one call at a time, from a worker thread (for a
/// progressive display). The reference renderer ("ref") renders by rows: each row is a
/// tile, called as it is finished.
using TileCallback = std::function<void(const Tile& tile)>;

/// Renders one scene on one device selection, frame after frame.
///
/// devices: "auto" (a GPU, else PoCL's CPU device, else another CPU device; never Mesa's
/// llvmpipe: docs/user-guide.md, "Which device"), "cpu", "gpu", "all", an index from
/// listDevices(), a list of indices ("0,2": the devices share each frame), or "ref", the
/// double-precision host reference renderer (no OpenCL needed). The Renderer keeps its own
/// copy of the scene (scene(), editable between frames). On OpenCL devices the scene is packed and uploaded on the first frame
/// and kept: later frames with another camera or settings cost only their rendering
/// (FrameStats::packSeconds and uploadSeconds are 0), except when the area-light samples or
/// the trilinear filter change, which reshape the packed tables.
///
/// Threads and processes:
/// - One Renderer is used by one thread at a time: its member functions must not run on two
///   threads at once (guard it with a mutex if it is shared). Only `cancel`, which any
///   thread may set, and the callbacks, which run on a worker thread while render() runs,
///   cross threads.
/// - Different Renderers may render on different threads at the same time, on the same or
///   different devices and scenes: each has its own copy of the scene, its own OpenCL
///   contexts, queues and buffers, and renders exactly what it renders alone (tested:
///   tests/test_api_concurrency.cpp). They share a device's cores, so each is slower.
/// - A Scene is a plain value: several threads may read one (e.g. each constructing a
///   Renderer from it) as long as none modifies it meanwhile.
/// - listDevices() and saveImage() may be called from any thread.
/// - Processes may share one kernel cache folder ($RAY_CACHE_DIR), even an empty one they
///   fill at once: each cache file is written whole under a temporary name and renamed
///   (tested with four processes: tests/concurrency.sh).
class Renderer {
public:
    /// Renders `scene` (copied) on `devices`. Throws DeviceError when the selection names no
    /// device, InputError for a bad name.
    explicit Renderer(const Scene& scene, const std::string& devices = "auto");
    /// Renders the caller's scene, shared rather than copied: an edit made through the
    /// pointer is the renderer's (for a front end whose scene object outlives the renderer
    /// or is held by it, as the Python module's renderer.scene). The same rule as for
    /// scene(): no edit while a frame renders.
    Renderer(std::shared_ptr<Scene> scene, const std::string& devices = "auto");
    ~Renderer();
    Renderer(Renderer&&) noexcept;  ///< takes the other's scene, devices and engine
    Renderer& operator=(Renderer&&) noexcept;  ///< takes the other's scene, devices and engine

    /// The scene it renders: its own copy, which the caller may edit between frames. Each
    /// frame takes the edits made since the last: on OpenCL devices only the tables an edit
    /// changed are packed and uploaded again (a material or light edit builds no BVH; moved
    /// primitives have their tree refitted), as FrameStats' pack, BVH and upload times show.
    Scene& scene();
    const Scene& scene() const;  ///< the scene it renders

    /// What the camera ray through the centre of pixel (x, y) of the current settings' size
    /// (row 0 at the top) meets first, with the current camera and the scene as it is now
    /// (edits included); nothing on the background. Found on the host in double precision
    /// (the pinhole ray, at shutter time 0), so every device selection gives the same
    /// answer. Throws InputError for a pixel outside the image.
    std::optional<Pick> pick(int x, int y);

    /// The device selection it was made with ("auto", "ref", "0,2", ...).
    const std::string& devices() const;
    /// Throws InputError for a camera the scenefile loader would refuse (a zero look
    /// direction, an up vector parallel to it, a height angle outside (0, 180)).
    void setCamera(const Camera& camera);
    Camera camera() const;  ///< the camera of the next frame (at first the scene's)
    /// Throws InputError for values out of range (sizes 1..16384, depth 0..64, ...).
    void setSettings(const Settings& settings);
    const Settings& settings() const;  ///< the settings of the next frame

    /// Renders into the caller's buffer of width × height × 3 floats (RGB, row 0 at the
    /// top, linear, unclamped). cancel (optional), set from any thread, stops the frame
    /// within about a second. Throws InputError when the buffer is too small, DeviceError.
    FrameStats render(float* rgb, size_t floatCount, const ProgressCallback& progress = {},
                      const std::atomic<bool>* cancel = nullptr, const TileCallback& onTile = {});
    /// The same into a new buffer (its stats, if wanted, into `stats`).
    std::vector<float> render(FrameStats* stats = nullptr);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The longest side of an image ray renders or saves.
constexpr int kMaxImageSide = 16384;

/// Writes width × height × 3 floats as an image whose format follows the extension (png,
/// jpg, ppm, tif: 8-bit, clamped and truncated as the course does; exr, hdr: floats).
/// The file is replaced whole or not at all (WriteOptions says what happens to links,
/// devices and read-only files). At most 16384 pixels a side, as a render. Throws
/// InputError, DeviceError.
void saveImage(const std::vector<float>& rgb, int width, int height, const std::filesystem::path& file);
/// saveImage(), with how a read-only file is treated (WriteOptions).
void saveImage(const std::vector<float>& rgb, int width, int height, const std::filesystem::path& file,
               const WriteOptions& options);

/// The same from 8-bit values (what toByte gives; a frame's bytes): written unchanged to
/// 8-bit formats, as v / 255 to float ones.
void saveImage(const std::vector<uint8_t>& rgb, int width, int height, const std::filesystem::path& file);
/// The same from 8-bit values, with how a read-only file is treated (WriteOptions).
void saveImage(const std::vector<uint8_t>& rgb, int width, int height, const std::filesystem::path& file,
               const WriteOptions& options);

/// The 8-bit value ray writes for a channel: floor(255 · clamp(c, 0, 1)), as in its PNGs.
uint8_t toByte(float channel);

}  // namespace ray::api
