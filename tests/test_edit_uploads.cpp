// What an edit costs the next frame (issue 43): the edit says what it changed (its change
// set, edit/operations.h), and the engine re-packs and uploads that alone, with no
// comparison of the scenes: a material edit uploads the materials table and nothing else;
// moving one of 10^4 spheres refits the BVH rather than rebuilding it. The frame's
// statistics (RenderStats::sceneUpdate, FrameStats::sceneUpdate) say which.
#include <catch2/catch.hpp>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "edit/edit_json.h"
#include "edit/edit_session.h"
#include "kernel_comparison.h"
#include "opencl/opencl_engine.h"
#include "opencl/packed_scene_cache.h"
#include "ray/ray.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace {

using namespace ray;
using Names = std::vector<std::string>;

LoadOptions quiet() { return ray::test::quietLoadOptions(); }

edit::EditSession shadowsSession() {
    return edit::EditSession(loadSceneDocument(test::scenesDir() / "shadows.xml", quiet()), {quiet(), true, {}});
}

void apply(edit::EditSession& session, const std::string& request) {
    session.apply(edit::operationFromJson(edit::parseTypedJson(request)).operation);
}

// Each table's bytes, by name.
std::vector<std::pair<std::string, std::vector<char>>> tableBytes(const PackedScene& packed) {
    std::vector<std::pair<std::string, std::vector<char>>> tables;
    packed.forEachBuffer([&](const auto& table, SceneBufferName name) {
        const char* bytes = reinterpret_cast<const char*>(table.data());
        tables.emplace_back(name.name, std::vector<char>(bytes, bytes + table.size() * sizeof(table[0])));
    });
    return tables;
}

}  // namespace

TEST_CASE("An edit's change set names every packed table whose bytes it changed, and no other", "[incremental][edit]") {
    edit::EditSession session = shadowsSession();
    engine::PackedSceneCache cache(session.scene(), true);
    RenderStats stats;
    const RenderSettings settings;
    cache.update(settings, stats, [] {});
    CHECK(stats.sceneUpdate.packing == "full");
    const std::vector<std::pair<std::string, Names>> edits = {
        {R"({"op": "set", "node": "object-1", "fields": {"diffuse": [1, 0, 0]}})", {"materials"}},
        {R"({"op": "set", "node": "light-1", "fields": {"position": [0, 6, 1]}})", {"lights"}},
        {R"({"op": "set", "node": "object-2", "fields": {"world": [1,0,0,0.5, 0,1,0,0.25, 0,0,1,0]}})",
         {"nodes", "cpuNodes", "primitives", "motions"}},
        {R"({"op": "set", "node": "globals", "fields": {"ambientcoeff": 0.3}})", {}},
    };
    for (const auto& [request, expected] : edits) {
        INFO(request);
        const std::shared_ptr<const PackedScene> before = cache.packed();
        const auto beforeBytes = tableBytes(*before);
        apply(session, request);
        cache.setScene(session.scene());
        stats = {};
        cache.update(settings, stats, [] {});
        CHECK(stats.sceneUpdate.packing == "edit");  // the globals: no table, the launch parameters
        CHECK(stats.sceneUpdate.tables == expected);
        const auto afterBytes = tableBytes(*cache.packed());
        for (size_t i = 0; i < afterBytes.size(); ++i) {
            INFO(afterBytes[i].first);
            if (afterBytes[i].second != beforeBytes[i].second)
                CHECK(cache.packed()->versions[i] != before->versions[i]);  // uploaded again
            const bool named = std::find(expected.begin(), expected.end(), afterBytes[i].first) != expected.end();
            CHECK(named == (cache.packed()->versions[i] != before->versions[i]));
        }
    }
}

TEST_CASE("After a material edit the engine uploads the materials alone, the frame says so and renders as a fresh "
          "engine does",
          "[incremental][edit][engine][kernel]") {
    auto device = test::cpuDevice();
    if (!device) return test::skip("no OpenCL CPU device");
    edit::EditSession session = shadowsSession();
    const RenderSettings settings = test::settingsFromOptions("--aa off", 48, 40, 2);
    OpenClEngine engine(session.scene(), std::vector<OpenClDevice>{*device});
    const RenderedFrame first = engine.renderFrame(session.scene()->camera, settings);
    CHECK(first.stats.sceneUpdate.bvh == "rebuilt");
    apply(session, R"({"op": "set", "node": "object-2", "fields": {"diffuse": [1, 0, 1]}})");
    engine.setScene(session.scene());
    const RenderedFrame second = engine.renderFrame(session.scene()->camera, settings);
    CHECK(second.stats.sceneUpdate.packing == "edit");
    CHECK(second.stats.sceneUpdate.bvh == "kept");
    CHECK(second.stats.sceneUpdate.tables == Names{"materials"});
    CHECK(second.stats.bvhBuildSeconds == 0);
    OpenClEngine fresh(*session.scene(), std::vector<OpenClDevice>{*device});
    CHECK(second.image.rgb == fresh.renderFrame(session.scene()->camera, settings).image.rgb);
}

TEST_CASE("Moving one of 10^4 spheres refits the BVH rather than rebuilding it (the C++ API's frame statistics)",
          "[incremental][edit][engine][kernel][api]") {
    auto device = test::cpuDevice();
    if (!device) return test::skip("no OpenCL CPU device");
    namespace api = ray::api;
    api::Scene scene;
    scene.setCamera({{0, 0, 150}, {0, 0, -1}, {0, 1, 0}, 60, 0, 0});
    scene.addLight(api::Light{});
    const int material = scene.addMaterial({});
    std::vector<int> spheres;
    for (int i = 0; i < 10000; ++i)
        spheres.push_back(scene.addPrimitive(api::Shape::Sphere,
                                             api::Transform::translate({double(i % 100) - 50, double(i / 100) - 50, 0}),
                                             material));
    api::Renderer renderer(scene, "cpu");
    api::Settings small;
    small.width = 32;
    small.height = 24;
    small.antialias = api::Antialias::Off;
    renderer.setSettings(small);
    api::FrameStats stats;
    renderer.render(&stats);
    CHECK(stats.sceneUpdate.bvh == "rebuilt");
    renderer.scene().setObjectToWorld(spheres[5050], api::Transform::translate({0, 0, 20}));
    renderer.render(&stats);
    CHECK(stats.sceneUpdate.packing == "edit");
    CHECK(stats.sceneUpdate.bvh == "refit");
    CHECK(stats.bvhBuildSeconds == 0);
    CHECK(std::find(stats.sceneUpdate.tables.begin(), stats.sceneUpdate.tables.end(), "materials") ==
          stats.sceneUpdate.tables.end());
    // Orbiting the camera re-packs nothing.
    api::Camera orbit = renderer.camera();
    orbit.position = {10, 0, 150};
    renderer.setCamera(orbit);
    renderer.render(&stats);
    CHECK(stats.sceneUpdate.packing == "none");
    CHECK(stats.sceneUpdate.tables.empty());
    // A material edit: the materials alone.
    api::Material red;
    red.diffuse = {1, 0, 0};
    renderer.scene().setMaterial(spheres[0], red);
    renderer.render(&stats);
    CHECK(stats.sceneUpdate.tables == Names{"materials"});
}
