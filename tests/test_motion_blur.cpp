// Motion blur: the <motion> extension of the scene format, the BVH bounds that cover a
// motion, --shutter, and the kernel against the reference renderer.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "accel/bvh.h"
#include "kernel_comparison.h"
#include "reference/reference_bvh.h"
#include "reference/reference_renderer.h"
#include "scene/scene_loader.h"
#include "test_support.h"

using Catch::Matchers::Contains;
using ray::Vec3;

namespace {

// A scene whose root holds `body` (transblocks), with a camera and a light.
std::string sceneWith(const std::string& body) {
    return R"(<scenefile>
  <cameradata><pos x="0" y="0" z="5"/><focus x="0" y="0" z="0"/><up x="0" y="1" z="0"/>
    <heightangle v="45"/></cameradata>
  <lightdata><id v="0"/><type v="point"/><color r="1" g="1" b="1"/><position x="0" y="3" z="5"/></lightdata>
  <object type="tree" name="root">
)" + body + R"(
  </object>
</scenefile>
)";
}

struct Loaded {
    ray::Scene scene;
    std::vector<std::string> warnings;
};

Loaded load(const std::string& xml, ray::LoadOptions options = {}) {
    Loaded result;
    options.warn = [&result](const std::string& w) { result.warnings.push_back(w); };
    result.scene = ray::loadSceneFromText(xml, "motion.xml", options);
    return result;
}

bool near(const Vec3& a, const Vec3& b) { return length(a - b) < 1e-12; }

const char* kSphere = R"(<object type="primitive" name="sphere"><diffuse r="1" g="0" b="0"/></object>)";

}  // namespace

TEST_CASE("a transblock's <motion> becomes its primitives' world-space motion", "[loader][motion]") {
    Loaded loaded = load(sceneWith(std::string(R"(<transblock><translate x="1" y="0" z="0"/><motion x="0" y="2" z="0"/>)") +
                                   kSphere + "</transblock><transblock>" + kSphere + "</transblock>"));
    REQUIRE(loaded.scene.primitives.size() == 2);
    CHECK(near(loaded.scene.primitives[0].motion, {0, 2, 0}));
    CHECK(near(loaded.scene.primitives[1].motion, {0, 0, 0}));  // a block without <motion> stands still
    CHECK(loaded.warnings.empty());
}

TEST_CASE("<motion> is in the parent's frame, wherever it stands among the transforms", "[loader][motion]") {
    // The parent frame is scaled by 2 and turned 90° about z: x there is 2·y in the world.
    // The block's own scale (listed before and after the motion) does not touch it.
    for (const char* order : {"<motion x=\"1\" y=\"0\" z=\"0\"/><scale x=\"5\" y=\"5\" z=\"5\"/>",
                              "<scale x=\"5\" y=\"5\" z=\"5\"/><motion x=\"1\" y=\"0\" z=\"0\"/>"}) {
        Loaded loaded = load(sceneWith(std::string(R"(<transblock><rotate x="0" y="0" z="1" angle="90"/>
            <scale x="2" y="2" z="2"/><object type="tree"><transblock>)") +
                                       order + kSphere + "</transblock></object></transblock>"));
        REQUIRE(loaded.scene.primitives.size() == 1);
        Vec3 m = loaded.scene.primitives[0].motion;
        CHECK(std::abs(m.x) < 1e-12);
        CHECK(m.y == Approx(2));
        CHECK(std::abs(m.z) < 1e-12);
    }
}

TEST_CASE("nested motions add, through subtrees and masters", "[loader][motion]") {
    std::string xml = R"(<scenefile>
  <object type="tree" name="ball"><transblock><motion x="0" y="0" z="3"/>)" +
                      std::string(kSphere) + R"(</transblock></object>
  <object type="tree" name="root">
    <transblock><motion x="1" y="0" z="0"/>
      <object type="tree"><transblock><motion x="0" y="2" z="0"/><object type="master" name="ball"/></transblock></object>
    </transblock>
    <transblock><object type="master" name="ball"/></transblock>
  </object>
</scenefile>)";
    Loaded loaded = load(xml);
    REQUIRE(loaded.scene.primitives.size() == 2);
    CHECK(near(loaded.scene.primitives[0].motion, {1, 2, 3}));
    CHECK(near(loaded.scene.primitives[1].motion, {0, 0, 3}));
}

TEST_CASE("a bad <motion> is an error at its line, a second one warns", "[loader][motion]") {
    std::string missing = sceneWith(std::string("<transblock>\n<motion x=\"1\" y=\"2\"/>") + kSphere + "</transblock>");
    CHECK_THROWS_WITH(load(missing), Contains("motion.xml:7: error:"));
    std::string notNumber =
        sceneWith(std::string("<transblock>\n<motion x=\"1\" y=\"fast\" z=\"0\"/>") + kSphere + "</transblock>");
    CHECK_THROWS_WITH(load(notNumber), Contains("motion.xml:7: error:") && Contains("fast"));

    std::string twice = sceneWith(std::string("<transblock>\n<motion x=\"1\" y=\"0\" z=\"0\"/>\n"
                                              "<motion x=\"0\" y=\"1\" z=\"0\"/>") +
                                  kSphere + "</transblock>");
    Loaded loaded = load(twice);
    REQUIRE(loaded.warnings.size() == 1);
    CHECK_THAT(loaded.warnings[0], Contains("motion.xml:8: warning:") && Contains("add up"));
    CHECK(near(loaded.scene.primitives[0].motion, {1, 1, 0}));
    ray::LoadOptions strict;
    strict.strict = true;
    CHECK_THROWS_WITH(load(twice, strict), Contains("motion.xml:8: error:"));
}

TEST_CASE("a moving sphere's bounds cover its whole motion in both BVHs", "[bvh][motion]") {
    ray::PrimitiveInstance sphere;
    sphere.type = ray::PrimitiveType::Sphere;
    sphere.objectToWorld = ray::Affine::translation({1, 0, 0});
    sphere.worldToObject = ray::Affine::translation({-1, 0, 0});
    sphere.motion = {2, -3, 0.5};
    // The unit-diameter sphere at (1, 0, 0) at t = 0 and at (3, −3, 0.5) at t = 1.
    const Vec3 lo{0.5, -3.5, -0.5}, hi{3.5, 0.5, 1.0};

    ray::BoundingBox kernelBox = ray::worldBounds(sphere);
    ray::reference::Aabb referenceBox = ray::reference::worldBounds(sphere);
    for (int axis = 0; axis < 3; ++axis) {
        INFO("axis " << axis);
        CHECK(kernelBox.min[axis] <= lo[axis]);
        CHECK(kernelBox.max[axis] >= hi[axis]);
        CHECK(kernelBox.min[axis] == Approx(lo[axis]).margin(1e-5));
        CHECK(kernelBox.max[axis] == Approx(hi[axis]).margin(1e-5));
        CHECK(referenceBox.lo[axis] <= lo[axis]);
        CHECK(referenceBox.hi[axis] >= hi[axis]);
        CHECK(referenceBox.lo[axis] == Approx(lo[axis]).margin(1e-5));
        CHECK(referenceBox.hi[axis] == Approx(hi[axis]).margin(1e-5));
    }

    // And the reference intersector finds the sphere where it is at each time: a ray down
    // the z axis through (3, −3) hits it at t = 1 only, through (1, 0) at t = 0 only.
    ray::Scene scene;
    scene.primitives.push_back(sphere);
    ray::reference::SceneIntersector intersector(scene);
    CHECK(intersector.closestHit({1, 0, 5}, {0, 0, -1}, 0, INFINITY, 0));
    CHECK_FALSE(intersector.closestHit({1, 0, 5}, {0, 0, -1}, 0, INFINITY, 1));
    CHECK(intersector.closestHit({3, -3, 5}, {0, 0, -1}, 0, INFINITY, 1));
    CHECK_FALSE(intersector.anyHit({3, -3, 5}, {0, 0, -1}, 0, INFINITY, 0));
    CHECK(intersector.anyHit({2, -1.5, 5}, {0, 0, -1}, 0, INFINITY, 0.5));
}

TEST_CASE("shutter 0 renders the scene at rest, in both renderers", "[motion][kernel]") {
    // The motion scene with every <motion> removed, against the scene at shutter 0.
    ray::LoadOptions quiet;
    quiet.warn = [](const std::string&) {};
    ray::Scene moving = ray::loadScene(ray::test::scenesDir() / "motion_blur.xml", quiet);
    ray::Scene still = moving;
    for (ray::PrimitiveInstance& p : still.primitives) p.motion = {};
    ray::RenderSettings settings = ray::test::settingsFromOptions("--aa stratified --samples 4 --shutter 0", 64, 48);
    ray::RenderSettings open = ray::test::settingsFromOptions("--aa stratified --samples 4", 64, 48);

    ray::Image stillImage = ray::renderReference(still, settings);
    CHECK(ray::test::compare8bit(ray::renderReference(moving, settings), stillImage, 0).maxError == 0);
    CHECK(ray::test::compare8bit(ray::renderReference(moving, open), stillImage, 0).maxError > 0);  // it does move

    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    ray::Image stillKernel = ray::renderOpenCl(*device, still, settings, {}, nullptr);
    CHECK(ray::test::compare8bit(ray::renderOpenCl(*device, moving, settings, {}, nullptr), stillKernel, 0).maxError ==
          0);
}

TEST_CASE("kernel matches host with motion blur", "[kernel][kvh][motion]") {
    auto device = ray::test::cpuDevice();
    if (!device) return ray::test::skip("no OpenCL CPU device");
    ray::test::compareKernelWithHost(*device, ray::test::scenesDir() / "motion_blur.xml",
                                     ray::test::settingsFromOptions("--aa stratified --samples 4", 160, 120),
                                     "motion_blur_stratified4");
    ray::test::compareKernelWithHost(*device, ray::test::scenesDir() / "motion_blur.xml",
                                     ray::test::settingsFromOptions("--aa stratified --samples 4 --shutter 0.5", 160, 120),
                                     "motion_blur_shutter_half");
}

TEST_CASE("the shutter option takes a fraction of the motion", "[cli][motion]") {
    CHECK(ray::test::settingsFromOptions("", 8, 8).shutter == 1);
    CHECK(ray::test::settingsFromOptions("--shutter 0.25", 8, 8).shutter == 0.25);
    CHECK(ray::test::settingsFromOptions("--shutter 0", 8, 8).shutter == 0);
    CHECK_THROWS_AS(ray::test::settingsFromOptions("--shutter 1.5", 8, 8), ray::UsageError);
    CHECK_THROWS_AS(ray::test::settingsFromOptions("--shutter -0.1", 8, 8), ray::UsageError);
    CHECK_THROWS_AS(ray::test::settingsFromOptions("--shutter nan", 8, 8), ray::UsageError);
}
