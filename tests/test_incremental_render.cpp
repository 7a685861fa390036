// Edits between frames (host/scene/scene_difference.h, opencl_engine.h setScene): the engine
// packs and uploads only what an edit changed, builds no BVH for a material or light edit
// nor for moved primitives (their tree is refitted), and renders what a fresh engine renders.
#include <catch2/catch.hpp>

#include <cstring>
#include <memory>
#include <vector>

#include "opencl/opencl_engine.h"
#include "opencl/scene_packing.h"
#include "scene/scene_difference.h"
#include "scene/scene_loader.h"
#include "kernel_comparison.h"
#include "test_support.h"

namespace {

ray::Image renderFresh(const ray::OpenClDevice& device, const ray::Scene& scene, const ray::RenderSettings& settings) {
    ray::OpenClEngine engine(scene, std::vector<ray::OpenClDevice>{device});
    return engine.renderFrame(scene.camera, settings).image;
}

}  // namespace

TEST_CASE("compareScenes tells a material, a light and a move apart", "[incremental]") {
    const ray::Scene scene = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    CHECK_FALSE(ray::compareScenes(scene, scene).any());

    ray::Scene recolored = scene;
    recolored.materials[1].diffuse = {1, 0, 0};
    ray::SceneDifference d = ray::compareScenes(scene, recolored);
    CHECK(d.materials);
    CHECK_FALSE(d.geometry);
    CHECK_FALSE(d.lights);

    ray::Scene lit = scene;
    lit.lights[0].color = {0.5, 0.5, 0.5};
    d = ray::compareScenes(scene, lit);
    CHECK(d.lights);
    CHECK_FALSE(d.materials);
    CHECK_FALSE(d.geometry);

    ray::Scene moved = scene;
    moved.primitives[1].objectToWorld = ray::Affine::translation({0, 0.5, 0}) * moved.primitives[1].objectToWorld;
    moved.primitives[1].worldToObject = moved.primitives[1].objectToWorld.inverse();
    d = ray::compareScenes(scene, moved);
    CHECK(d.geometry);
    CHECK(d.transformsOnly);

    // Bytes that differ for equal values (-0 for 0) are no difference: the byte-wise fast
    // path falls back to comparing field by field.
    ray::Scene signedZero = scene;
    REQUIRE(signedZero.primitives[1].objectToWorld.m[0][1] == 0.0);
    signedZero.primitives[1].objectToWorld.m[0][1] = -0.0;
    CHECK_FALSE(ray::compareScenes(scene, signedZero).any());

    ray::Scene reshaped = scene;
    reshaped.primitives[1].type = ray::PrimitiveType::Sphere;
    d = ray::compareScenes(scene, reshaped);
    CHECK(d.geometry);
    CHECK_FALSE(d.transformsOnly);
}

TEST_CASE("After a material or light edit the engine uploads that table only and builds no BVH",
          "[incremental][engine][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    auto scene = std::make_shared<ray::Scene>(ray::loadScene(ray::test::scenesDir() / "shadows.xml"));
    const ray::RenderSettings settings = ray::test::settingsFromOptions("--aa off", 48, 40, 2);
    ray::OpenClEngine engine(scene, std::vector<ray::OpenClDevice>{*device});
    ray::RenderedFrame first = engine.renderFrame(scene->camera, settings);
    CHECK(first.stats.bvhBuildSeconds > 0);

    auto recolored = std::make_shared<ray::Scene>(*scene);
    recolored->materials[recolored->primitives[2].material].diffuse = {1, 0, 0};
    engine.setScene(recolored);
    ray::RenderedFrame second = engine.renderFrame(recolored->camera, settings);
    CHECK(second.stats.bvhBuildSeconds == 0);
    CHECK(second.stats.packSeconds > 0);
    CHECK(second.stats.uploadSeconds > 0);
    CHECK(second.image.rgb != first.image.rgb);
    CHECK(second.image.rgb == renderFresh(*device, *recolored, settings).rgb);

    auto lit = std::make_shared<ray::Scene>(*recolored);
    lit->lights[0].position = {2, 5, 3};
    engine.setScene(lit);
    ray::RenderedFrame third = engine.renderFrame(lit->camera, settings);
    CHECK(third.stats.bvhBuildSeconds == 0);
    CHECK(third.image.rgb == renderFresh(*device, *lit, settings).rgb);

    // The same scene again (an edit undone to an equal copy): nothing packed or uploaded.
    engine.setScene(std::make_shared<ray::Scene>(*lit));
    ray::RenderedFrame fourth = engine.renderFrame(lit->camera, settings);
    CHECK(fourth.stats.packSeconds == 0);
    CHECK(fourth.stats.uploadSeconds == 0);
    CHECK(fourth.image.rgb == third.image.rgb);
}

TEST_CASE("repackScene changes only the tables an edit touches", "[incremental]") {
    const ray::Scene scene = ray::loadScene(ray::test::scenesDir() / "shadows.xml");
    const ray::PackedScene packed = ray::packScene(scene);
    ray::Scene recolored = scene;
    recolored.materials[1].diffuse = {1, 0, 0};
    auto edited = ray::repackScene(packed, recolored, {}, ray::compareScenes(scene, recolored));
    REQUIRE(edited);
    CHECK(edited->bvhBuildSeconds == 0);
    CHECK(edited->materials[1].diffuse.x == 1.0f);
    CHECK(edited->materials[1].diffuse.y == 0.0f);
    const ray::PackedScene fresh = ray::packScene(recolored);
    CHECK(std::memcmp(edited->materials.data(), fresh.materials.data(), fresh.materials.size() * sizeof(fresh.materials[0])) == 0);
    CHECK(std::memcmp(edited->nodes.data(), packed.nodes.data(), packed.nodes.size() * sizeof(packed.nodes[0])) == 0);

    ray::Scene reshaped = scene;
    reshaped.primitives.pop_back();
    CHECK_FALSE(ray::repackScene(packed, reshaped, {}, ray::compareScenes(scene, reshaped)));
}

TEST_CASE("Moved primitives get a refitted tree, not a new one, and render as a fresh engine renders them",
          "[incremental][engine][kernel]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    auto scene = std::make_shared<ray::Scene>(ray::loadScene(ray::test::scenesDir() / "shadows.xml"));
    const ray::RenderSettings settings = ray::test::settingsFromOptions("--aa off", 48, 40, 2);
    ray::OpenClEngine engine(scene, std::vector<ray::OpenClDevice>{*device});
    ray::RenderedFrame first = engine.renderFrame(scene->camera, settings);

    auto moved = std::make_shared<ray::Scene>(*scene);
    for (size_t i : {size_t(1), size_t(2)}) {
        ray::PrimitiveInstance& p = moved->primitives[i];
        p.objectToWorld = ray::Affine::translation({0.3, 0.6, -0.4}) * p.objectToWorld;
        p.worldToObject = p.objectToWorld.inverse();
    }
    engine.setScene(moved);
    ray::RenderedFrame second = engine.renderFrame(moved->camera, settings);
    CHECK(second.stats.bvhBuildSeconds == 0);
    CHECK(second.image.rgb != first.image.rgb);
    CHECK(second.image.rgb == renderFresh(*device, *moved, settings).rgb);
}
