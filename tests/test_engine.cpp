// The persistent engine (host/opencl/opencl_engine.h): one packing and upload for many
// frames, each with its own camera and settings, tiles reported as they finish.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "devices/renderer.h"
#include "opencl/kernel_arguments.h"
#include "opencl/kernel_source.h"
#include "opencl/kernel_variant.h"
#include "opencl/opencl_engine.h"
#include "opencl/opencl_renderer.h"
#include "scene/scene_loader.h"
#include "kernel_comparison.h"
#include "test_support.h"

namespace {

// A fresh one-frame render of the scene seen from `camera`.
ray::Image renderFresh(const ray::OpenClDevice& device, ray::Scene scene, const ray::Camera& camera,
                       const ray::RenderSettings& settings) {
    scene.camera = camera;
    return ray::renderOpenCl(device, scene, settings, {}, nullptr);
}

}  // namespace

TEST_CASE("The engine packs and uploads once, and renders each frame as a fresh render would", "[engine][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    ray::Scene scene = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    ray::RenderSettings settings = ray::test::settingsFromOptions("--aa off", 48, 40, 2);
    ray::OpenClEngine engine(scene, std::vector<ray::OpenClDevice>{*device});

    std::mutex mutex;
    size_t tilePixels = 0;
    ray::FrameRequest request;
    request.tileSize = 16;
    request.onTile = [&](const ray::FinishedTile& t) {
        std::lock_guard lock(mutex);
        tilePixels += size_t(t.rect.width) * size_t(t.rect.height);
    };
    ray::RenderedFrame first = engine.renderFrame(scene.camera, settings, request);
    CHECK(first.stats.uploadSeconds > 0);
    CHECK(tilePixels == 48u * 40u);  // every pixel reported once, through 3 x 3 tiles
    CHECK(first.stats.devices.at(0).tiles == 9);
    CHECK(first.stats.device == device->description());
    CHECK(first.image.rgb == renderFresh(*device, scene, scene.camera, settings).rgb);

    // Another camera and image size: nothing packed or uploaded again.
    ray::Camera moved = scene.camera;
    moved.position = moved.position + ray::Vec3{0.5, 0.25, 0};
    ray::RenderSettings wider = settings;
    wider.width = 56;
    ray::RenderedFrame second = engine.renderFrame(moved, wider, request);
    CHECK(second.stats.packSeconds == 0);
    CHECK(second.stats.uploadSeconds == 0);
    CHECK(second.image.rgb == renderFresh(*device, scene, moved, wider).rgb);
    CHECK(second.image.rgb != first.image.rgb);
}

TEST_CASE("renderTile declares its arguments where the engine sets them", "[engine][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    cl::Context context(device->device);
    for (bool packets : {false, true}) {
        INFO((packets ? "packet build" : "one ray a work-item"));
        cl::Program program(context, ray::kernelProgramSource());
        const ray::KernelVariant variant{.cpuThreads = true, .lanes = packets ? 4 : 1};
        const std::string options = "-cl-std=CL1.2 -cl-kernel-arg-info -DRAY_MAX_FRAMES=2" + variant.buildDefine();
        program.build({device->device}, options.c_str());
        cl::Kernel kernel(program, "renderTile");
        auto nameOf = [&](cl_uint argument) {
            return std::string(kernel.getArgInfo<CL_KERNEL_ARG_NAME>(argument).c_str());
        };

        namespace argument = ray::kernel_argument;
        REQUIRE(kernel.getInfo<CL_KERNEL_NUM_ARGS>() == argument::count(packets));
        CHECK(nameOf(argument::kParams) == "params");
        std::vector<std::string> sceneBuffers;
        ray::PackedScene().forEachBuffer(
            [&](const auto&, ray::SceneBufferName buffer) { sceneBuffers.push_back(buffer.name); });
        REQUIRE(sceneBuffers.size() == ray::kSceneBufferCount);
        for (size_t i = 0; i < sceneBuffers.size(); ++i)
            CHECK(nameOf(argument::kFirstSceneBuffer + cl_uint(i)) == sceneBuffers[i]);
        CHECK(nameOf(argument::kTileColors) == "tileColors");
        CHECK(nameOf(argument::kTileRayCounts) == "tileRayCounts");
        if (packets) CHECK(nameOf(argument::kBlockQueue) == "blockQueue");
    }
}

TEST_CASE("The engine drops a failing device and fails only when none is left", "[engine][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    ray::Scene scene = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    ray::RenderSettings settings = ray::test::settingsFromOptions("--aa off", 32, 32, 2);
    ray::TestHooks hooks;
    hooks.failDevice = {0, 0};  // device 0 fails before its first tile
    ray::OpenClEngine engine(scene, std::vector<ray::OpenClDevice>{*device}, hooks);
    CHECK_THROWS_AS(engine.renderFrame(scene.camera, settings), ray::DeviceError);
    CHECK(engine.devicesLeft() == 0);
    CHECK_THROWS_AS(engine.renderFrame(scene.camera, settings), ray::DeviceError);
}

TEST_CASE("An 8-bit frame holds the bytes an 8-bit file of the float frame holds", "[engine][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    // Reflections and highlights: values above 1 (clamped) and between the 8-bit steps.
    ray::Scene scene = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    ray::RenderSettings settings = ray::test::settingsFromOptions("--aa course", 45, 37, 3);
    ray::OpenClEngine engine(scene, std::vector<ray::OpenClDevice>{*device});
    ray::FrameRequest request;
    request.tileSize = 16;  // tiles cut at the right and bottom edges too
    const ray::RenderedFrame floats = engine.renderFrame(scene.camera, settings, request);
    request.eightBit = true;
    const ray::RenderedFrame bytes = engine.renderFrame(scene.camera, settings, request);
    CHECK(bytes.image.empty());
    REQUIRE(bytes.bytes.width == 45);
    REQUIRE(bytes.bytes.height == 37);
    CHECK(bytes.bytes.rgb == ray::quantize8(floats.image).rgb);

    // The files are the same, byte for byte.
    const auto folder = std::filesystem::temp_directory_path() / ("ray_test_engine_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    ray::writeImage(floats.image, folder / "floats.png");
    ray::writeImage(bytes.bytes, folder / "bytes.png");
    CHECK(ray::test::readFileBytes(folder / "floats.png") == ray::test::readFileBytes(folder / "bytes.png"));
    CHECK_THROWS_AS(ray::writeImage(bytes.bytes, folder / "bytes.exr"), ray::ImageError);
    std::filesystem::remove_all(folder);
}

TEST_CASE("A device still building takes no part in a frame and keeps building for the next", "[engine][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    ray::Scene scene = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    ray::RenderSettings settings = ray::test::settingsFromOptions("--aa off", 40, 32, 2);
    const ray::Image alone = renderFresh(*device, scene, scene.camera, settings);
    // The same device twice: two slots, each with its own context, queue and program.
    ray::TestHooks hooks;
    hooks.slowBuild = {1, 3};  // device 1's build takes 3 s longer
    ray::OpenClEngine engine(scene, std::vector<ray::OpenClDevice>{*device, *device}, hooks);
    ray::FrameRequest request;
    request.tileSize = 8;
    ray::RenderedFrame first = engine.renderFrame(scene.camera, settings, request);
    CHECK(first.image.rgb == alone.rgb);
    REQUIRE(first.stats.devices.size() == 2);
    CHECK(first.stats.devices[1].building);
    CHECK(first.stats.devices[1].tiles == 0);
    CHECK(first.stats.devices[0].tiles == 20);  // every tile of the 5 x 4
    // The build goes on between frames (were it restarted for each short frame, with its
    // 3 s delay, device 1 would never be ready).
    bool ready = false;
    for (int frame = 0; frame < 600 && !ready; ++frame) {
        ray::RenderedFrame next = engine.renderFrame(scene.camera, settings, request);
        CHECK(next.image.rgb == alone.rgb);
        ready = !next.stats.devices[1].building;
        if (!ready) usleep(100000);
    }
    CHECK(ready);
    CHECK(engine.devicesLeft() == 2);
}

TEST_CASE("A hung device is dropped, the frames stay whole, and the engine goes without waiting for it",
          "[engine][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    ray::Scene scene = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    ray::RenderSettings settings = ray::test::settingsFromOptions("--aa off", 40, 32, 2);
    const ray::Image alone = renderFresh(*device, scene, scene.camera, settings);
    // Device 1 stops answering after 2 launches; device 0 starts 3 s late, so that it has them.
    ray::TestHooks hooks;
    hooks.slowBuild = {0, 3};
    hooks.hangDevice = {1, 2};
    {
        ray::OpenClEngine engine(scene, std::vector<ray::OpenClDevice>{*device, *device}, hooks);
        ray::FrameRequest request;
        request.tileSize = 8;
        ray::RenderedFrame first = engine.renderFrame(scene.camera, settings, request);
        CHECK(first.image.rgb == alone.rgb);
        REQUIRE(first.stats.devices.size() == 2);
        CHECK(first.stats.devices[1].failed);
        CHECK_THAT(first.stats.devices[1].failure, Catch::Matchers::Contains("stopped answering"));
        CHECK(first.stats.warnings.size() == 1);
        CHECK(engine.devicesLeft() == 1);
        // The engine lives on with the device that answers.
        ray::RenderedFrame second = engine.renderFrame(scene.camera, settings, request);
        CHECK(second.image.rgb == alone.rgb);
        CHECK(second.stats.devices[0].tiles == 20);  // every tile of the 5 x 4
        CHECK(second.stats.warnings.empty());  // said once
    }  // the destructor leaves the hung device's thread: were it joined, this test would hang
}
