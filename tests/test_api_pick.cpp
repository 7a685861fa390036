// Renderer::pick and Renderer::scene (include/ray/renderer.h): what a pixel shows, the same
// on every device, and frames that take the renderer's scene as edited since the last.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "ray/ray.h"
#include "kernel_comparison.h"
#include "test_support.h"

namespace {

namespace api = ray::api;

api::Settings sized(int width, int height) {
    api::Settings settings;
    settings.width = width;
    settings.height = height;
    settings.antialias = api::Antialias::Off;
    return settings;
}

}  // namespace

TEST_CASE("API: pick finds the object under a pixel, nothing on the background, the same on every device",
          "[api][pick]") {
    const api::Scene scene = api::Scene::load(ray::test::scenesDir() / "shadows.xml").scene;
    std::vector<std::string> selections{"ref"};
    if (ray::test::cpuDevice()) selections.push_back("cpu");
    std::vector<std::optional<api::Pick>> centres, corners;
    for (const std::string& devices : selections) {
        api::Renderer renderer(scene, devices);
        renderer.setSettings(sized(80, 60));
        centres.push_back(renderer.pick(40, 30));
        corners.push_back(renderer.pick(0, 0));
    }
    for (size_t i = 0; i < selections.size(); ++i) {
        INFO(selections[i]);
        REQUIRE(centres[i]);
        CHECK_FALSE(corners[i]);
        CHECK(centres[i]->instance == centres[0]->instance);
        CHECK(centres[i]->point.x == centres[0]->point.x);
        CHECK(centres[i]->distance == centres[0]->distance);
    }
    const api::Pick& hit = *centres[0];
    CHECK(hit.instance < scene.primitiveCount());
    CHECK(hit.object >= 0);  // the scenefile's <object type="primitive"> it comes from
    CHECK(hit.object == scene.objectOfInstance(hit.instance));
    CHECK(hit.distance > 0);
    const double n = std::sqrt(hit.normal.x * hit.normal.x + hit.normal.y * hit.normal.y + hit.normal.z * hit.normal.z);
    CHECK(n == Approx(1.0));
    // The point lies along the camera's view, at the distance from the eye.
    const api::Camera camera = scene.camera();
    const api::Vec3 d{hit.point.x - camera.position.x, hit.point.y - camera.position.y, hit.point.z - camera.position.z};
    CHECK(std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) == Approx(hit.distance));

    api::Renderer renderer(scene, "ref");
    renderer.setSettings(sized(80, 60));
    CHECK_THROWS_AS(renderer.pick(80, 0), api::InputError);
    CHECK_THROWS_AS(renderer.pick(0, -1), api::InputError);
}

TEST_CASE("API: pick sees the renderer's scene as edited, and a later camera", "[api][pick]") {
    const api::Scene scene = api::Scene::load(ray::test::scenesDir() / "shadows.xml").scene;
    api::Renderer renderer(scene, "ref");
    renderer.setSettings(sized(80, 60));
    REQUIRE_FALSE(renderer.pick(0, 0));
    // A large sphere in front of the camera now covers the corner.
    const int material = renderer.scene().addMaterial({});
    api::Camera camera = scene.camera();
    renderer.scene().addPrimitive(api::Shape::Sphere,
                                  api::Transform::translate({camera.position.x, camera.position.y, camera.position.z}) *
                                      api::Transform::scale({4, 4, 4}),
                                  material);
    const auto inside = renderer.pick(0, 0);
    REQUIRE(inside);
    CHECK(inside->instance == scene.primitiveCount());
    // Placed in code: an object of the scene's own, as the scene names it.
    CHECK(inside->object == renderer.scene().objectOfInstance(inside->instance));
    CHECK(inside->object >= 0);
    CHECK(inside->distance == Approx(2.0));
}

TEST_CASE("API: a frame after a light edit uploads the lights and builds no BVH, a new primitive builds one",
          "[api][pick][kernel]") {
    if (!ray::test::cpuDevice()) return ray::test::skip("no OpenCL CPU device");
    const api::Scene scene = api::Scene::load(ray::test::scenesDir() / "shadows.xml").scene;
    api::Renderer renderer(scene, "cpu");
    renderer.setSettings(sized(48, 40));
    api::FrameStats first;
    const std::vector<float> before = renderer.render(&first);
    CHECK(first.bvhBuildSeconds > 0);

    api::Light light;
    light.position = {2, 4, 2};
    light.color = {0.3, 0.3, 0.3};
    renderer.scene().addLight(light);
    api::FrameStats second;
    const std::vector<float> lit = renderer.render(&second);
    CHECK(second.bvhBuildSeconds == 0);
    CHECK(second.uploadSeconds > 0);
    CHECK(lit != before);
    api::Renderer fresh(renderer.scene(), "cpu");
    fresh.setSettings(sized(48, 40));
    CHECK(lit == fresh.render());

    // Nothing changed: nothing packed or uploaded.
    api::FrameStats third;
    CHECK(renderer.render(&third) == lit);
    CHECK(third.packSeconds == 0);
    CHECK(third.uploadSeconds == 0);

    renderer.scene().addPrimitive(api::Shape::Sphere, api::Transform::translate({0, 1.5, 0}),
                                  renderer.scene().addMaterial({}));
    api::FrameStats fourth;
    renderer.render(&fourth);
    CHECK(fourth.bvhBuildSeconds > 0);
}
