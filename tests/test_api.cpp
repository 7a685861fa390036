// The public C++ API (include/ray/): loading, building, rendering frames, errors.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <limits>

#include "image/image.h"
#include "ray/ray.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
namespace api = ray::api;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

api::Settings small(int width = 64, int height = 48) {
    api::Settings settings;
    settings.width = width;
    settings.height = height;
    return settings;
}

std::vector<float> renderFresh(const api::Scene& scene, const std::string& devices, const api::Settings& settings,
                               api::FrameStats* stats = nullptr) {
    api::Renderer renderer(scene, devices);
    renderer.setSettings(settings);
    return renderer.render(stats);
}

// scenes/primitive_sphere.xml, built in code.
api::Scene sphereSceneInCode() {
    api::Scene scene;
    scene.setGlobals({0.5, 0.5, 0.5, 0.5});
    api::Camera camera;
    camera.position = {0, 1, 4};
    camera.look = {0, -1, -4};
    camera.up = {0, 1, 0};
    camera.heightAngleDegrees = 40;
    scene.setCamera(camera);
    api::Light light;
    light.position = {3, 4, 5};
    scene.addLight(light);
    api::Material material;
    material.diffuse = {0.3, 0.9, 0.3};
    material.ambient = {0.1, 0.1, 0.1};
    material.specular = {0.6, 0.6, 0.6};
    material.shininess = 20;
    const int green = scene.addMaterial(material);
    using T = api::Transform;
    scene.addPrimitive(api::Shape::Sphere,
                       T::translate({0, 0, 0}) * T::rotate({1, 1, 0}, 25) * T::scale({1.5, 1.5, 1.5}), green);
    return scene;
}

// The CLI's 64x48 render of a bundled scene on the reference renderer, with extra options.
ray::Image renderWithCli(const std::string& sceneName, const std::vector<std::string>& options, const std::string& png) {
    std::vector<std::string> args = {(ray::test::scenesDir() / sceneName).string(), "64", "48", "--device", "ref",
                                     "--quiet", "-o", (ray::test::outputDir() / png).string()};
    args.insert(args.end(), options.begin(), options.end());
    auto run = ray::test::runRay(args);
    REQUIRE(run.exitCode == 0);
    return ray::readImage(ray::test::outputDir() / png);
}

// How many 8-bit values of an API render differ from the CLI's image.
size_t bytesDiffering(const std::vector<float>& rgb, const ray::Image& cli) {
    REQUIRE(rgb.size() == cli.rgb.size());
    size_t differing = 0;
    for (size_t i = 0; i < rgb.size(); ++i) differing += api::toByte(rgb[i]) != ray::quantize8(cli.rgb[i]);
    return differing;
}

// A boolean Settings member is the CLI's switch `option`: off by default (the image then
// differs from the switch's), and with it on the API renders the CLI's image exactly.
void checkSwitchIsCliOption(const std::string& sceneName, const std::string& option, bool api::Settings::*member) {
    const ray::Image cli = renderWithCli(sceneName, {option}, "api_cli_" + option.substr(2) + ".png");
    auto [loaded, warnings] = api::Scene::load(ray::test::scenesDir() / sceneName);
    api::Settings settings = small();
    CHECK_FALSE(settings.*member);
    CHECK(bytesDiffering(renderFresh(loaded, "ref", settings), cli) > 0);
    settings.*member = true;
    CHECK(bytesDiffering(renderFresh(loaded, "ref", settings), cli) == 0);
}

// Whether an OpenCL CPU device is there (PoCL); tests of it skip without one.
bool haveCpuDevice() {
    for (const api::Device& device : api::listDevices())
        if (device.cpu) return true;
    return false;
}

}  // namespace

TEST_CASE("API: a loaded scene renders what the CLI writes", "[api]") {
    const ray::Image cli = renderWithCli("shadows.xml", {}, "api_cli_shadows.png");
    auto [loaded, warnings] = api::Scene::load(ray::test::scenesDir() / "shadows.xml");
    CHECK(warnings.empty());
    CHECK(bytesDiffering(renderFresh(loaded, "ref", small()), cli) == 0);
}

TEST_CASE("API: Settings::fresnel is the CLI's --fresnel, off by default", "[api][fresnel]") {
    checkSwitchIsCliOption("refraction.xml", "--fresnel", &api::Settings::fresnel);
}

TEST_CASE("API: Settings::courseMeshes is the CLI's --course-meshes, off by default", "[api][course-meshes]") {
    checkSwitchIsCliOption("mesh_vase.xml", "--course-meshes", &api::Settings::courseMeshes);
}

TEST_CASE("API: warnings come back to the caller, errors carry file and line", "[api]") {
    const std::string xml = "<scenefile>\n<cameradata bogus=\"1\">\n<pos x=\"0\" y=\"0\" z=\"5\"/>\n</cameradata>\n"
                            "<object type=\"tree\" name=\"root\"></object>\n</scenefile>\n";
    auto [scene, warnings] = api::Scene::fromString(xml, "in_memory.xml");
    REQUIRE(warnings.size() == 1);
    CHECK_THAT(warnings[0], Catch::Contains("in_memory.xml:2: warning"));

    const std::string broken = "<scenefile>\n<object type=\"tree\" name=\"root\">\n<transblock>\n</scenefile>\n";
    try {
        api::Scene::fromString(broken, "broken.xml");
        FAIL("no exception");
    } catch (const api::InputError& e) {
        CHECK(e.file() == "broken.xml");
        CHECK(e.line() > 0);
        CHECK_THAT(e.what(), Catch::Contains("broken.xml:"));
    }
    CHECK_THROWS_AS(api::Scene::load("/nonexistent/scene.xml"), api::InputError);
    api::LoadOptions strict;
    strict.strict = true;
    CHECK_THROWS_AS(api::Scene::fromString(xml, "in_memory.xml", strict), api::InputError);
}

TEST_CASE("API: a scene built in code renders as its scenefile does", "[api]") {
    const api::Scene built = sphereSceneInCode();
    const api::Scene loaded = api::Scene::load(ray::test::scenesDir() / "primitive_sphere.xml").scene;
    CHECK(built.primitiveCount() == 1);
    const std::vector<float> a = renderFresh(built, "ref", small());
    const std::vector<float> b = renderFresh(loaded, "ref", small());
    REQUIRE(a.size() == b.size());
    size_t differing = 0;
    for (size_t i = 0; i < a.size(); ++i) differing += api::toByte(a[i]) != api::toByte(b[i]);
    CHECK(differing == 0);
    // The sphere is in the middle of the frame, green.
    const size_t centre = (size_t(24) * 64 + 32) * 3;
    CHECK(a[centre + 1] > a[centre]);
    CHECK(a[centre + 1] > 0.2f);
}

TEST_CASE("API: textures from memory and meshes from arrays", "[api]") {
    api::Scene scene;
    api::Camera camera;
    camera.position = {0, 0, 3};
    camera.look = {0, 0, -1};
    scene.setCamera(camera);
    api::Light light;
    light.position = {0, 0, 5};
    scene.addLight(light);
    // A 2x1 texture: red on the left, blue on the right.
    const int texture = scene.addTextureFromPixels(2, 1, {1, 0, 0, 0, 0, 1});
    api::Material material;
    material.diffuse = {1, 1, 1};
    material.blend = 1;
    material.texture.texture = texture;
    const int textured = scene.addMaterial(material);
    // A unit quad facing the camera, two triangles with (u, v).
    const int quad = scene.addMesh({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, {0, 1, 2, 0, 2, 3}, {},
                                   {0, 0, 1, 0, 1, 1, 0, 1});
    scene.addPrimitive(api::Shape::Mesh, api::Transform(), textured, quad);
    api::Settings settings = small(32, 32);
    settings.antialias = api::Antialias::Off;
    const std::vector<float> rgb = renderFresh(scene, "ref", settings);
    auto pixel = [&](int x, int y) { return &rgb[(size_t(y) * 32 + size_t(x)) * 3]; };
    CHECK(pixel(12, 16)[0] > 0.5f);
    CHECK(pixel(12, 16)[2] < 0.1f);
    CHECK(pixel(20, 16)[2] > 0.5f);
    CHECK(pixel(20, 16)[0] < 0.1f);

    CHECK_THROWS_AS(scene.addMesh({0, 0, 0}, {0, 0, 1}), api::InputError);
    CHECK_THROWS_AS(scene.addPrimitive(api::Shape::Sphere, api::Transform(), 7), api::InputError);
    CHECK_THROWS_AS(scene.addPrimitive(api::Shape::Cube, api::Transform::scale({0, 1, 1}), textured), api::InputError);
    CHECK_THROWS_AS(scene.addTextureFromFile("/nonexistent.png"), api::InputError);
}

TEST_CASE("API: one renderer, three frames of a moving camera, each equal to a fresh render", "[api][kernel]") {
    const api::Scene scene = api::Scene::load(ray::test::scenesDir() / "primitives_all.xml").scene;
    for (const std::string devices : {"ref", "cpu"}) {
        DYNAMIC_SECTION(devices) {
            if (devices == "cpu" && !haveCpuDevice()) {
                ray::test::skip("no OpenCL CPU device");
                return;
            }
            api::Renderer renderer(scene, devices);
            renderer.setSettings(small());
            api::Camera camera = scene.camera();
            for (int frame = 0; frame < 3; ++frame) {
                camera.position.x += 0.25;
                renderer.setCamera(camera);
                CHECK(renderer.camera().position.x == camera.position.x);
                api::FrameStats stats;
                const std::vector<float> moving = renderer.render(&stats);
                CHECK(stats.primaryRays > 0);
                if (devices == "cpu") {
                    // The scene is packed and uploaded by the first frame only.
                    if (frame == 0) CHECK(stats.uploadSeconds > 0);
                    else CHECK((stats.packSeconds == 0 && stats.uploadSeconds == 0));
                }
                api::Scene fresh = scene;
                fresh.setCamera(camera);
                CHECK(moving == renderFresh(fresh, devices, small()));
            }
        }
    }
}

namespace {

// Renders a frame of small() on `devices` and checks that its tiles cover every pixel once
// and hold the frame's pixels.
void checkTilesCoverTheFrameOnce(const std::string& devices) {
    api::Renderer renderer(sphereSceneInCode(), devices);
    renderer.setSettings(small());
    std::vector<float> rgb(64 * 48 * 3);
    std::vector<int> covered(64 * 48, 0);
    std::vector<float> fromTiles(rgb.size(), -1.0f);
    renderer.render(rgb.data(), rgb.size(), {}, nullptr, [&](const api::Tile& tile) {
        for (int y = 0; y < tile.height; ++y)
            for (int x = 0; x < tile.width; ++x) {
                const size_t pixel = size_t(tile.y + y) * 64 + size_t(tile.x + x);
                ++covered[pixel];
                for (size_t c = 0; c < 3; ++c)
                    fromTiles[pixel * 3 + c] = tile.rgb[(size_t(y) * size_t(tile.width) + size_t(x)) * 3 + c];
            }
    });
    CHECK(fromTiles == rgb);  // the tiles hold the frame's pixels
    CHECK(std::all_of(covered.begin(), covered.end(), [](int n) { return n == 1; }));
}

}  // namespace

TEST_CASE("API: the tile callback sees every pixel of an OpenCL frame once", "[api][kernel]") {
    if (!haveCpuDevice()) {
        ray::test::skip("no OpenCL CPU device");
        return;
    }
    checkTilesCoverTheFrameOnce("cpu");
}

TEST_CASE("API: the reference renderer's rows are tiles that see every pixel once", "[api]") {
    checkTilesCoverTheFrameOnce("ref");
}

TEST_CASE("API: cancellation, progress, and refused settings and buffers", "[api]") {
    const api::Scene scene = sphereSceneInCode();
    api::Renderer renderer(scene, "ref");
    renderer.setSettings(small());
    std::vector<float> rgb(64 * 48 * 3, 0.5f);
    std::atomic<bool> cancel{true};
    api::FrameStats stats = renderer.render(rgb.data(), rgb.size(), {}, &cancel);
    CHECK(stats.cancelled);

    double last = 0;
    stats = renderer.render(rgb.data(), rgb.size(), [&](double fraction) { last = std::max(last, fraction); });
    CHECK_FALSE(stats.cancelled);
    CHECK(last > 0.5);

    CHECK_THROWS_AS(renderer.render(rgb.data(), 10), api::InputError);
    api::Settings bad = small();
    bad.width = 0;
    CHECK_THROWS_AS(renderer.setSettings(bad), api::InputError);
    CHECK_THROWS_AS(api::Renderer(scene, "tpu"), api::Error);
    CHECK_THROWS_AS(api::saveImage(rgb, 64, 48, ray::test::outputDir() / "api.xyz"), api::InputError);
    const fs::path saved = ray::test::outputDir() / "api_saved.png";
    api::saveImage(rgb, 64, 48, saved);
    CHECK(ray::readImage(saved).width == 64);
}

TEST_CASE("API: materials, lights and cameras follow the scenefile loader's rules", "[api]") {
    api::Scene scene = sphereSceneInCode();
    api::Material material;
    material.shininess = -5;
    CHECK_THROWS_WITH(scene.addMaterial(material), Contains("shininess must be 0 or more, not -5"));
    material = {};
    material.ior = 0;
    CHECK_THROWS_WITH(scene.addMaterial(material), Contains("ior must be more than 0, not 0"));
    api::Light light;
    light.attenuation = {1, -1, 0};
    CHECK_THROWS_WITH(scene.addLight(light), Contains("attenuation must be 0 or more in each component"));
    api::Camera camera = scene.camera();
    camera.look = {0, 0, 0};
    CHECK_THROWS_WITH(scene.setCamera(camera), Contains("the camera looks nowhere"));
    camera = scene.camera();
    camera.heightAngleDegrees = 180;
    CHECK_THROWS_AS(scene.setCamera(camera), api::InputError);
    api::Renderer renderer(scene, "ref");
    CHECK_THROWS_AS(renderer.setCamera(camera), api::InputError);
    CHECK(renderer.devices() == "ref");
    CHECK(scene.lightCount() == 1);  // nothing refused was added
}

TEST_CASE("API: settings out of range are refused with plain numbers", "[api]") {
    api::Renderer renderer(sphereSceneInCode(), "ref");
    api::Settings bad = small();
    bad.width = 0;
    CHECK_THROWS_WITH(renderer.setSettings(bad), Equals("error: width must be between 1 and 16384, not 0"));
    bad = small();
    bad.threshold = 1.5;
    CHECK_THROWS_WITH(renderer.setSettings(bad), Equals("error: threshold must be between 0 and 1, not 1.5"));
}

TEST_CASE("API: 8-bit pixels are saved as they are", "[api]") {
    api::Renderer renderer(sphereSceneInCode(), "ref");
    renderer.setSettings(small());
    const std::vector<float> rgb = renderer.render();
    std::vector<uint8_t> bytes(rgb.size());
    std::transform(rgb.begin(), rgb.end(), bytes.begin(), api::toByte);
    const fs::path fromBytes = ray::test::outputDir() / "api_bytes.png";
    const fs::path fromFloats = ray::test::outputDir() / "api_floats.png";
    api::saveImage(bytes, 64, 48, fromBytes);
    api::saveImage(rgb, 64, 48, fromFloats);
    CHECK(ray::readImage(fromBytes).rgb == ray::readImage(fromFloats).rgb);
    CHECK_THROWS_AS(api::saveImage(bytes, 64, 47, fromBytes), api::InputError);
    CHECK(std::string(api::version()) == RAY_VERSION);
}

TEST_CASE("API: numbers a scenefile cannot hold are refused everywhere, transforms included", "[api]") {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    api::Scene scene = sphereSceneInCode();
    api::Light light;
    light.position = {nan, 0, 0};
    CHECK_THROWS_WITH(scene.addLight(light), Contains("position must be a finite number in each component, not (nan"));
    light = {};
    light.direction = {0, inf, 0};
    CHECK_THROWS_AS(scene.addLight(light), api::InputError);
    CHECK_THROWS_AS(scene.setLight(0, light), api::InputError);
    api::Camera camera = scene.camera();
    camera.position = {0, 0, nan};
    CHECK_THROWS_WITH(scene.setCamera(camera), Contains("position must be a finite number"));
    camera = scene.camera();
    camera.aperture = inf;
    CHECK_THROWS_AS(scene.setCamera(camera), api::InputError);
    CHECK_THROWS_WITH(scene.setGlobals({nan, 0.5, 0.5, 0.5}), Contains("ka must be a finite number"));
    CHECK_THROWS_WITH(api::Transform::rotate({0, 0, 0}, 30), Contains("the axis (0, 0, 0) has no direction"));
    CHECK_THROWS_AS(api::Transform::rotate({0, 1, 0}, nan), api::InputError);
    CHECK_THROWS_AS(api::Transform::translate({inf, 0, 0}), api::InputError);
    CHECK_THROWS_AS(api::Transform::scale({1, nan, 1}), api::InputError);
    api::Transform bad;
    bad.m[1][3] = nan;
    CHECK_THROWS_WITH(scene.setObjectToWorld(scene.objects().front().id, bad), Contains("not finite"));
    CHECK(scene.lightCount() == 1);
    CHECK(std::isfinite(scene.camera().position.z));
}

TEST_CASE("API: a file name of any length gets a short message, not a crash", "[api]") {
    for (size_t length : {size_t(5000), size_t(50000), size_t(100000)}) {
        try {
            api::Scene::load(std::string(length, 'x') + ".xml");
            FAIL("loaded");
        } catch (const api::InputError& e) {
            CHECK(std::string(e.what()).size() < 400);
            CHECK_THAT(e.what(), Contains("cannot open the scene file"));
        }
        try {
            api::Scene::fromString("<bad", std::string(length, 'n'));
            FAIL("parsed");
        } catch (const api::InputError& e) {
            CHECK(std::string(e.what()).size() < 500);
            CHECK(e.line() == 1);
        }
    }
}
