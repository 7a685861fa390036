// The scene loader and the file-reference search (SPEC §1), rule by rule.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "scene/file_search.h"
#include "image/image.h"
#include "scene/scene_loader.h"
#include "scene_text.h"
#include "test_support.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using ray::InputError;
using ray::LoadOptions;
using ray::Scene;
using ray::Vec3;

namespace {

// ---------------------------------------------------------------------------------------
// Helpers

using Loaded = ray::test::LoadedText;

// Loads XML text as "test.xml" (or `file`), collecting the warnings.
Loaded load(const std::string& xml, LoadOptions options = {}, const fs::path& file = "test.xml") {
    return ray::test::loadText(xml, file, std::move(options));
}

// The message of the InputError that loading throws ("" when it loads).
std::string errorOf(const std::string& xml, LoadOptions options = {}, const fs::path& file = "test.xml") {
    return ray::test::loadError(xml, file, std::move(options));
}

LoadOptions strictOptions() {
    LoadOptions options;
    options.strict = true;
    return options;
}

// "<scenefile>" around `body`.
std::string scenefile(const std::string& body) { return "<scenefile>\n" + body + "\n</scenefile>\n"; }

// A scene whose root tree holds `blocks`.
std::string rootScene(const std::string& blocks, const std::string& rest = "") {
    return scenefile(rest + "<object type=\"tree\" name=\"root\">\n" + blocks + "\n</object>");
}

// One transblock with `content`.
std::string block(const std::string& content) { return "<transblock>\n" + content + "\n</transblock>\n"; }

std::string primitive(const std::string& name = "cube", const std::string& material = "") {
    return "<object type=\"primitive\" name=\"" + name + "\">" + material + "</object>\n";
}

// "test.xml:LINE: " for the first line of `xml` that contains `needle`.
std::string at(const std::string& xml, const std::string& needle, const std::string& file = "test.xml") {
    size_t position = xml.find(needle);
    REQUIRE(position != std::string::npos);
    int line = 1;
    for (size_t i = 0; i < position; ++i) line += xml[i] == '\n';
    return file + ":" + std::to_string(line) + ": ";
}

bool near(const Vec3& a, const Vec3& b, double eps = 1e-9) {
    return std::abs(a.x - b.x) < eps && std::abs(a.y - b.y) < eps && std::abs(a.z - b.z) < eps;
}

bool near(const ray::Affine& a, const ray::Affine& b, double eps = 1e-9) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            if (std::abs(a.m[i][j] - b.m[i][j]) > eps) return false;
    return true;
}

// A fresh, empty folder for one test.
fs::path tempFolder(const std::string& name) {
    fs::path folder = fs::temp_directory_path() / ("ray_test_loader_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(folder);
    fs::create_directories(folder);
    return folder;
}

void writeText(const fs::path& file, const std::string& text) {
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << text;
}

// A small valid PNG, written with the project's own image writer.
void writePng(const fs::path& file) {
    fs::create_directories(file.parent_path());
    ray::Image image(2, 1);
    image.set(0, 0, {1, 0, 0});
    image.set(1, 0, {0, 0, 1});
    ray::writeImage(image, file);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Defaults

TEST_CASE("defaults are the course parser's", "[loader]") {
    Loaded loaded = load(rootScene(block(primitive())), {});
    const Scene& s = loaded.scene;
    CHECK(loaded.warnings.empty());
    CHECK(s.globals.ka == 0.5);
    CHECK(s.globals.kd == 0.5);
    CHECK(s.globals.ks == 0.5);
    CHECK(s.globals.kt == 0.5);
    CHECK(s.camera.position == Vec3(5, 5, 5));
    CHECK(s.camera.look == Vec3(-1, -1, -1));
    CHECK(s.camera.up == Vec3(0, 1, 0));
    CHECK(s.camera.heightAngleDegrees == 45);
    CHECK(s.camera.aperture == 0);
    CHECK(s.lights.empty());
    REQUIRE(s.materials.size() == 1);
    const ray::Material& m = s.materials[0];
    CHECK(m.diffuse == Vec3(1, 1, 1));
    CHECK(m.ambient == Vec3(0, 0, 0));
    CHECK(m.specular == Vec3(0, 0, 0));
    CHECK(m.reflective == Vec3(0, 0, 0));
    CHECK(m.transparent == Vec3(0, 0, 0));
    CHECK(m.emissive == Vec3(0, 0, 0));
    CHECK(m.shininess == 0);
    CHECK(m.blend == 0);
    CHECK(m.texture.image == -1);
    CHECK(m.bumpMap.image == -1);
    REQUIRE(s.primitives.size() == 1);
    CHECK(near(s.primitives[0].objectToWorld, ray::Affine::identity()));
    CHECK(s.primitives[0].mesh == -1);
}

TEST_CASE("a light without fields is a white point light at (3,3,3)", "[loader]") {
    Scene s = load(rootScene("", "<lightdata><id v=\"0\"/></lightdata>\n")).scene;
    REQUIRE(s.lights.size() == 1);
    CHECK(s.lights[0].type == ray::LightType::Point);
    CHECK(s.lights[0].color == Vec3(1, 1, 1));
    CHECK(s.lights[0].position == Vec3(3, 3, 3));
    CHECK(s.lights[0].attenuation == Vec3(1, 0, 0));
}

// ---------------------------------------------------------------------------------------
// globaldata, cameradata, lightdata

TEST_CASE("globaldata sets the four coefficients", "[loader]") {
    Scene s = load(rootScene("", R"(<globaldata>
  <ambientcoeff v="0.1"/><diffusecoeff v="0.2"/><specularcoeff v="0.3"/><transparentcoeff v="0.4"/>
</globaldata>
)")).scene;
    CHECK(s.globals.ka == 0.1);
    CHECK(s.globals.kd == 0.2);
    CHECK(s.globals.ks == 0.3);
    CHECK(s.globals.kt == 0.4);
}

TEST_CASE("cameradata reads every field, aspectratio is ignored", "[loader]") {
    Scene s = load(rootScene("", R"(<cameradata>
  <pos x="1" y="2" z="3"/><look x="0" y="0" z="-1"/><up x="1" y="0" z="0"/>
  <heightangle v="60"/><aspectratio v="2"/><aperture v="0.25"/><focallength v="7"/>
</cameradata>
)")).scene;
    CHECK(s.camera.position == Vec3(1, 2, 3));
    CHECK(s.camera.look == Vec3(0, 0, -1));
    CHECK(s.camera.up == Vec3(1, 0, 0));
    CHECK(s.camera.heightAngleDegrees == 60);
    CHECK(s.camera.aperture == 0.25);
    CHECK(s.camera.focalLength == 7);
}

TEST_CASE("focus is a point: look = focus - pos, whatever their order", "[loader]") {
    Scene s = load(rootScene("", R"(<cameradata>
  <focus x="1" y="1" z="1"/><pos x="1" y="1" z="4"/>
</cameradata>
)")).scene;
    CHECK(s.camera.look == Vec3(0, 0, -3));
}

TEST_CASE("material and light values without a meaning are errors at their line", "[loader]") {
    const std::pair<const char*, const char*> refused[] = {
        {"<shininess v=\"-5\"/>", "shininess must be 0 or more, not -5"},
        {"<ior v=\"0\"/>", "ior must be more than 0, not 0"},
        {"<blend v=\"1.5\"/>", "blend must be between 0 and 1, not 1.5"},
        {"<diffuse r=\"1\" g=\"-1\" b=\"0\"/>", "diffuse must be 0 or more in each component, not (1, -1, 0)"},
    };
    for (const auto& [element, message] : refused) {
        const std::string xml =
            rootScene(block(std::string("<object type=\"primitive\" name=\"sphere\">\n") + element + "\n</object>"));
        CHECK_THAT(errorOf(xml), Contains(at(xml, element) + "error: " + message));
    }
    const std::pair<const char*, const char*> lights[] = {
        {"<angle v=\"0\"/>", "angle must be more than 0 and at most 180, not 0"},
        {"<penumbra v=\"-1\"/>", "penumbra must be 0 or more, not -1"},
        {"<function v1=\"1\" v2=\"-0.5\" v3=\"0\"/>", "function must be 0 or more in each component"},
        {"<width v=\"0\"/>", "width must be more than 0, not 0"},
        {"<color r=\"-1\" g=\"1\" b=\"1\"/>", "color must be 0 or more in each component"},
    };
    for (const auto& [element, message] : lights) {
        const std::string xml = rootScene("", std::string("<lightdata>\n<type v=\"spot\"/>\n") + element + "\n</lightdata>\n");
        CHECK_THAT(errorOf(xml), Contains(at(xml, element) + "error: " + message));
    }
    // What the course's scenes hold stays valid: colors above 1, a penumbra wider than the cone.
    CHECK_NOTHROW(ray::loadSceneFromText(
        rootScene(block("<object type=\"primitive\" name=\"cube\"><diffuse r=\"80\" g=\"80\" b=\"80\"/></object>"),
                  "<lightdata><type v=\"spot\"/><penumbra v=\"80\"/></lightdata>\n"),
        "test.xml", {}));
}

TEST_CASE("look and focus together are an error", "[loader]") {
    std::string xml = rootScene("", R"(<cameradata>
  <look x="0" y="0" z="-1"/>
  <focus x="0" y="0" z="0"/>
</cameradata>
)");
    std::string error = errorOf(xml);
    CHECK_THAT(error, Contains(at(xml, "<focus") + "error: "));
    CHECK_THAT(error, Contains("both <look> and <focus>"));
}

TEST_CASE("a camera that cannot form a view is an error", "[loader]") {
    CHECK_THAT(errorOf(rootScene("", "<cameradata><look x=\"0\" y=\"0\" z=\"0\"/></cameradata>")),
               Contains("looks nowhere"));
    CHECK_THAT(errorOf(rootScene("", "<cameradata><look x=\"0\" y=\"2\" z=\"0\"/></cameradata>")),
               Contains("parallel"));
    CHECK_THAT(errorOf(rootScene("", "<cameradata><heightangle v=\"180\"/></cameradata>")),
               Contains("heightangle"));
}

TEST_CASE("every light type and field", "[loader]") {
    Scene s = load(rootScene("", R"(<lightdata><id v="0"/><type v="point"/><color r="0.5" g="0.25" b="1"/>
  <function v1="1" v2="0.5" v3="0.25"/><position x="1" y="2" z="3"/></lightdata>
<lightdata><id v="1"/><type v="directional"/><direction x="0" y="-1" z="0"/></lightdata>
<lightdata><id v="2"/><type v="spot"/><position x="0" y="5" z="0"/><direction x="0" y="-1" z="0"/>
  <angle v="30"/><penumbra v="5"/><radius v="2"/></lightdata>
<lightdata><id v="3"/><type v="area"/><position x="0" y="4" z="0"/><direction x="0" y="-1" z="0"/>
  <width v="2"/><height v="3"/><color r="1" g="1" b="1" a="0.5"/></lightdata>
)")).scene;
    REQUIRE(s.lights.size() == 4);
    CHECK(s.lights[0].type == ray::LightType::Point);
    CHECK(s.lights[0].color == Vec3(0.5, 0.25, 1));
    CHECK(s.lights[0].attenuation == Vec3(1, 0.5, 0.25));
    CHECK(s.lights[0].position == Vec3(1, 2, 3));
    CHECK(s.lights[1].type == ray::LightType::Directional);
    CHECK(s.lights[1].direction == Vec3(0, -1, 0));
    CHECK(s.lights[2].type == ray::LightType::Spot);
    CHECK(s.lights[2].angleDegrees == 30);
    CHECK(s.lights[2].penumbraDegrees == 5);
    CHECK(s.lights[2].radius == 2);
    CHECK(s.lights[3].type == ray::LightType::Area);
    CHECK(s.lights[3].width == 2);
    CHECK(s.lights[3].height == 3);
    CHECK(s.lights[3].color == Vec3(1, 1, 1));  // the fourth value is ignored
}

TEST_CASE("an unknown light type is an error", "[loader]") {
    std::string xml = rootScene("", "<lightdata>\n<type v=\"laser\"/>\n</lightdata>\n");
    std::string error = errorOf(xml);
    CHECK_THAT(error, Contains(at(xml, "<type") + "error: unknown light type 'laser'"));
    CHECK_THAT(error, Contains("point, directional, spot or area"));
}

// ---------------------------------------------------------------------------------------
// Attributes are read by position

TEST_CASE("attributes are read by position, whatever their names", "[loader]") {
    Scene s = load(rootScene(block("<translate a=\"1\" b=\"2\" c=\"3\"/>" + primitive()),
                             "<lightdata><function v1=\"1\" v2=\"2\" v3=\"3\"/></lightdata>\n"
                             "<lightdata><function x=\"4\" y=\"5\" z=\"6\"/></lightdata>\n"))
                  .scene;
    CHECK(s.lights[0].attenuation == Vec3(1, 2, 3));
    CHECK(s.lights[1].attenuation == Vec3(4, 5, 6));
    CHECK(near(s.primitives[0].objectToWorld.transformPoint({0, 0, 0}), {1, 2, 3}));

    // Clock.xml spells type "typr".
    Scene clock = load(rootScene(block("<object typr=\"tree\">" + block(primitive("sphere")) + "</object>"))).scene;
    REQUIRE(clock.primitives.size() == 1);
    CHECK(clock.primitives[0].type == ray::PrimitiveType::Sphere);
}

TEST_CASE("too few values is an error, extra ones are warned about", "[loader]") {
    std::string xml = rootScene(block("<translate x=\"1\" y=\"2\"/>\n" + primitive()));
    std::string error = errorOf(xml);
    CHECK_THAT(error, Contains(at(xml, "<translate") + "error: <translate> needs 3 values (x y z) but has 2"));

    std::string extra = rootScene(block("<scale x=\"1\" y=\"1\" z=\"1\" w=\"2\"/>\n" + primitive()));
    Loaded loaded = load(extra);
    REQUIRE(loaded.warnings.size() == 1);
    CHECK_THAT(loaded.warnings[0], Contains(at(extra, "<scale") + "warning: unknown attribute 'w' of <scale>"));
}

// ---------------------------------------------------------------------------------------
// Transforms

TEST_CASE("transforms compose in the order listed: the last acts first", "[loader]") {
    Scene s = load(rootScene(block("<translate x=\"1\" y=\"0\" z=\"0\"/><scale x=\"2\" y=\"2\" z=\"2\"/>" + primitive()) +
                             block("<scale x=\"2\" y=\"2\" z=\"2\"/><translate x=\"1\" y=\"0\" z=\"0\"/>" + primitive()) +
                             block("<rotate x=\"0\" y=\"0\" z=\"1\" angle=\"90\"/>" + primitive())))
                  .scene;
    REQUIRE(s.primitives.size() == 3);
    CHECK(near(s.primitives[0].objectToWorld.transformPoint({1, 0, 0}), {3, 0, 0}));  // T(S p)
    CHECK(near(s.primitives[1].objectToWorld.transformPoint({1, 0, 0}), {4, 0, 0}));  // S(T p)
    CHECK(near(s.primitives[2].objectToWorld.transformPoint({1, 0, 0}), {0, 1, 0}));  // degrees, right-handed
}

TEST_CASE("a subtree's transforms act after its parent's: M = parent · T1 · … · Tn", "[loader]") {
    Scene s = load(rootScene(block("<translate x=\"0\" y=\"5\" z=\"0\"/>"
                                   "<object type=\"tree\">" +
                                   block("<scale x=\"3\" y=\"3\" z=\"3\"/>" + primitive()) + "</object>")))
                  .scene;
    REQUIRE(s.primitives.size() == 1);
    const ray::PrimitiveInstance& p = s.primitives[0];
    CHECK(near(p.objectToWorld.transformPoint({1, 1, 1}), {3, 8, 3}));
    CHECK(near(p.worldToObject * p.objectToWorld, ray::Affine::identity()));
}

TEST_CASE("worldToObject is the inverse of objectToWorld", "[loader]") {
    Scene s = load(rootScene(block("<translate x=\"1\" y=\"-2\" z=\"3\"/><rotate x=\"1\" y=\"1\" z=\"0\" angle=\"33\"/>"
                                   "<scale x=\"0.5\" y=\"2\" z=\"-4\"/>" + primitive())))
                  .scene;
    const ray::PrimitiveInstance& p = s.primitives[0];
    CHECK(near(p.worldToObject * p.objectToWorld, ray::Affine::identity()));
    CHECK(near(p.objectToWorld * p.worldToObject, ray::Affine::identity()));
}

TEST_CASE("matrix: row-major rows, translation in the last column", "[loader]") {
    Scene s = load(rootScene(block(R"(<matrix>
  <row0 v1="2" v2="0" v3="0" v4="1"/>
  <row1 v1="0" v2="3" v3="0" v4="2"/>
  <row2 v1="0" v2="0" v3="4" v4="3"/>
  <row3 v1="0" v2="0" v3="0" v4="1"/>
</matrix>
<translate x="1" y="1" z="1"/>)" + primitive())))
                  .scene;
    const ray::PrimitiveInstance& p = s.primitives[0];
    CHECK(near(p.objectToWorld.transformPoint({0, 0, 0}), {3, 5, 7}));  // M · T
    CHECK(near(p.worldToObject * p.objectToWorld, ray::Affine::identity()));
}

TEST_CASE("bad matrices are errors", "[loader]") {
    std::string rows3 = rootScene(block("<matrix>\n<row0 a=\"1\" b=\"0\" c=\"0\" d=\"0\"/></matrix>" + primitive()));
    CHECK_THAT(errorOf(rows3), Contains(at(rows3, "<matrix") + "error: <matrix> has 1 rows, not 4"));
    std::string projective = rootScene(block(R"(<matrix>
  <row0 v1="1" v2="0" v3="0" v4="0"/><row1 v1="0" v2="1" v3="0" v4="0"/><row2 v1="0" v2="0" v3="1" v4="0"/>
  <row3 v1="0" v2="0" v3="1" v4="1"/>
</matrix>)" + primitive()));
    CHECK_THAT(errorOf(projective), Contains(at(projective, "<row3") + "error: the matrix's last row is not 0 0 0 1"));
    std::string singular = rootScene(block(R"(<matrix>
  <row0 v1="1" v2="0" v3="0" v4="0"/><row1 v1="1" v2="0" v3="0" v4="0"/><row2 v1="0" v2="0" v3="1" v4="0"/>
  <row3 v1="0" v2="0" v3="0" v4="1"/>
</matrix>)" + primitive()));
    CHECK_THAT(errorOf(singular), Contains(at(singular, "<matrix") + "error: the matrix is singular"));
}

TEST_CASE("a singular transform is an error at its line", "[loader]") {
    std::string scale = rootScene(block("<scale x=\"1\" y=\"0\" z=\"1\"/>\n" + primitive()));
    CHECK_THAT(errorOf(scale), Contains(at(scale, "<scale") + "error: a zero scale"));
    std::string rotate = rootScene(block("<rotate x=\"0\" y=\"0\" z=\"0\" angle=\"30\"/>\n" + primitive()));
    CHECK_THAT(errorOf(rotate), Contains(at(rotate, "<rotate") + "error: the rotation axis is zero"));
}

TEST_CASE("transforms listed after objects still apply to the whole transblock", "[loader]") {
    // As the course's parser did; pdiddy.xml relies on it.
    Scene s = load(rootScene(block(primitive() + "<translate x=\"1\" y=\"2\" z=\"3\"/>"))).scene;
    CHECK(near(s.primitives[0].objectToWorld.transformPoint({0, 0, 0}), {1, 2, 3}));
}

TEST_CASE("an object outside a transblock is placed untransformed, with a warning", "[loader]") {
    std::string xml = rootScene(block(primitive()) + primitive("sphere"));
    Loaded loaded = load(xml);
    CHECK(loaded.scene.primitives.size() == 2);
    REQUIRE(loaded.warnings.size() == 1);
    CHECK_THAT(loaded.warnings[0], Contains(at(xml, "name=\"sphere\"") + "warning: <object> outside a <transblock>"));
}

// ---------------------------------------------------------------------------------------
// Primitives, masters and subtrees

TEST_CASE("every primitive type, names matched ignoring case", "[loader]") {
    Scene s = load(rootScene(block(primitive("cube") + primitive("sphere") + primitive("Cylinder") +
                                   primitive("cone") + primitive("TORUS"))))
                  .scene;
    REQUIRE(s.primitives.size() == 5);
    CHECK(s.primitives[0].type == ray::PrimitiveType::Cube);
    CHECK(s.primitives[1].type == ray::PrimitiveType::Sphere);
    CHECK(s.primitives[2].type == ray::PrimitiveType::Cylinder);
    CHECK(s.primitives[3].type == ray::PrimitiveType::Cone);
    CHECK(s.primitives[4].type == ray::PrimitiveType::Torus);
    CHECK(s.materials.size() == 5);
    CHECK(std::string(ray::primitiveTypeName(ray::PrimitiveType::Torus)) == "torus");
    CHECK(std::string(ray::primitiveTypeName(ray::PrimitiveType::Mesh)) == "mesh");
}

TEST_CASE("an unknown primitive is an error", "[loader]") {
    std::string xml = rootScene(block("\n" + primitive("triangle")));
    std::string error = errorOf(xml);
    CHECK_THAT(error, Contains(at(xml, "triangle") + "error: unknown primitive 'triangle'"));
    CHECK_THAT(error, Contains("use cube, sphere, cylinder, cone, torus or mesh"));
}

TEST_CASE("an unknown object type is an error", "[loader]") {
    CHECK_THAT(errorOf(rootScene(block("<object type=\"light\" name=\"x\"/>"))),
               Contains("unknown object type 'light'"));
}

TEST_CASE("masters instance a top-level tree and share its materials", "[loader]") {
    std::string xml = scenefile(R"(<object type="tree" name="root">
  <transblock><translate x="1" y="0" z="0"/><object type="master" name="pair"/></transblock>
  <transblock><translate x="0" y="1" z="0"/><object type="master" name="pair"/></transblock>
</object>
<object type="tree" name="pair">
  <transblock><object type="primitive" name="sphere"><diffuse r="1" g="0" b="0"/></object></transblock>
  <transblock><translate x="0" y="0" z="1"/><object type="primitive" name="cube"/></transblock>
</object>)");
    Scene s = load(xml).scene;
    REQUIRE(s.primitives.size() == 4);
    REQUIRE(s.materials.size() == 2);
    CHECK(s.primitives[0].material == s.primitives[2].material);
    CHECK(s.primitives[1].material == s.primitives[3].material);
    CHECK(s.primitives[0].material != s.primitives[1].material);
    CHECK(s.materials[s.primitives[0].material].diffuse == Vec3(1, 0, 0));
    CHECK(near(s.primitives[1].objectToWorld.transformPoint({0, 0, 0}), {1, 0, 1}));
    CHECK(near(s.primitives[3].objectToWorld.transformPoint({0, 0, 0}), {0, 1, 1}));
}

TEST_CASE("nested masters multiply, and load without per-instance materials", "[loader]") {
    // Level 0 is one sphere; level k places level k-1 four times: 4^8 = 65536 spheres, one material.
    std::string trees = "<object type=\"tree\" name=\"l0\">" + block(primitive("sphere")) + "</object>\n";
    for (int level = 1; level <= 8; ++level) {
        std::string inner = "<object type=\"master\" name=\"l" + std::to_string(level - 1) + "\"/>";
        trees += "<object type=\"tree\" name=\"l" + std::to_string(level) + "\">";
        for (int i = 0; i < 4; ++i)
            trees += block("<translate x=\"" + std::to_string(i) + "\" y=\"0\" z=\"0\"/><scale x=\"0.5\" y=\"0.5\" z=\"0.5\"/>" + inner);
        trees += "</object>\n";
    }
    Scene s = load(scenefile(trees + "<object type=\"tree\" name=\"root\">" +
                             block("<object type=\"master\" name=\"l8\"/>") + "</object>"))
                  .scene;
    CHECK(s.primitives.size() == 65536);
    CHECK(s.materials.size() == 1);
}

TEST_CASE("masters may name trees defined later, unused trees make no instances", "[loader]") {
    Scene s = load(scenefile("<object type=\"tree\" name=\"root\">" + block("<object type=\"master\" name=\"later\"/>") +
                             "</object><object type=\"tree\" name=\"later\">" + block(primitive()) +
                             "</object><object type=\"tree\" name=\"unused\">" + block(primitive("sphere")) + "</object>"))
                  .scene;
    CHECK(s.primitives.size() == 1);
    CHECK(s.materials.size() == 1);
}

TEST_CASE("an undefined master is an error naming it", "[loader]") {
    std::string xml = rootScene(block("\n<object type=\"master\" name=\"ghost\"/>"));
    std::string error = errorOf(xml);
    CHECK_THAT(error, Contains(at(xml, "ghost") + "error: no tree named 'ghost'"));
}

TEST_CASE("a cyclic master reference is an error naming the cycle", "[loader]") {
    std::string xml = scenefile(R"(<object type="tree" name="root">
  <transblock><object type="master" name="a"/></transblock>
</object>
<object type="tree" name="a">
  <transblock><object type="master" name="b"/></transblock>
</object>
<object type="tree" name="b">
  <transblock><object type="tree"><transblock><object type="master" name="a"/></transblock></object></transblock>
</object>)");
    std::string error = errorOf(xml);
    CHECK_THAT(error, Contains("error: cyclic master reference: a -> b -> a"));
    CHECK_THAT(error, Contains(at(xml, "name=\"a\"/></transblock></object>")));

    std::string self = rootScene(block("<object type=\"master\" name=\"root\"/>"));
    CHECK_THAT(errorOf(self), Contains("cyclic master reference: root -> root"));
}

TEST_CASE("a scene over the primitive limit is refused before flattening", "[loader]") {
    // Each level doubles: 2^40 instances, which must be counted, not made.
    std::string trees = "<object type=\"tree\" name=\"l0\">" + block(primitive()) + "</object>\n";
    for (int level = 1; level <= 40; ++level) {
        std::string inner = "<object type=\"master\" name=\"l" + std::to_string(level - 1) + "\"/>";
        trees += "<object type=\"tree\" name=\"l" + std::to_string(level) + "\">" + block(inner + inner) + "</object>\n";
    }
    std::string xml = scenefile(trees + "<object type=\"tree\" name=\"root\">" +
                                block("<object type=\"master\" name=\"l40\"/>") + "</object>");
    std::string error = errorOf(xml);
    CHECK_THAT(error, Contains("1099511627776 primitive instances"));
    CHECK_THAT(error, Contains("limit of 50000000"));

    LoadOptions small;
    small.maxPrimitives = 3;
    CHECK_THAT(errorOf(rootScene(block(primitive() + primitive() + primitive() + primitive())), small),
               Contains("4 primitive instances, more than the limit of 3"));
    CHECK(errorOf(rootScene(block(primitive() + primitive() + primitive())), small).empty());
}

TEST_CASE("the root tree is required, except in a file without trees", "[loader]") {
    std::string noRoot = scenefile("<object type=\"tree\" name=\"main\">" + block(primitive()) + "</object>");
    CHECK_THAT(errorOf(noRoot), Contains("test.xml:1: error: no tree named 'root'"));

    Loaded empty = load(scenefile("<globaldata/>"));
    CHECK(empty.scene.primitives.empty());
    REQUIRE(empty.warnings.size() == 1);
    CHECK_THAT(empty.warnings[0], Contains("it is empty"));
}

TEST_CASE("two top-level trees with one name are an error", "[loader]") {
    std::string xml = scenefile("<object type=\"tree\" name=\"root\"></object>\n<object type=\"tree\" name=\"root\"></object>");
    CHECK_THAT(errorOf(xml), Contains("test.xml:3: error: a second tree named 'root'"));
}

// ---------------------------------------------------------------------------------------
// Materials and textures

TEST_CASE("every material field", "[loader]") {
    Loaded loaded = load(rootScene(block(primitive("sphere", R"(
  <diffuse r="0.1" g="0.2" b="0.3"/><ambient r="0.4" g="0.5" b="0.6" a="1"/>
  <specular r="0.7" g="0.8" b="0.9"/><reflective r="1" g="0" b="0"/>
  <transparent r="0" g="1" b="0"/><emissive r="0" g="0" b="1"/>
  <shininess v="25"/><ior v="1.5"/><blend v="0.75"/>
  <texture file="nowhere/ray-test-no-texture.png" u="2" v="3"/><bumpmap file="nowhere/ray-test-no-bump.png"/>)"))));
    const ray::Material& m = loaded.scene.materials.at(0);
    CHECK(m.diffuse == Vec3(0.1, 0.2, 0.3));
    CHECK(m.ambient == Vec3(0.4, 0.5, 0.6));
    CHECK(m.specular == Vec3(0.7, 0.8, 0.9));
    CHECK(m.reflective == Vec3(1, 0, 0));
    CHECK(m.transparent == Vec3(0, 1, 0));
    CHECK(m.emissive == Vec3(0, 0, 1));
    CHECK(m.shininess == 25);
    CHECK(m.ior == 1.5);
    CHECK(m.blend == 0.75);
    CHECK(m.texture.repeatU == 2);
    CHECK(m.texture.repeatV == 3);
    CHECK(m.bumpMap.repeatU == 1);
    CHECK(m.bumpMap.repeatV == 1);
    // Neither file exists: warnings, and the surface keeps its colors.
    CHECK(m.texture.image == -1);
    CHECK(m.bumpMap.image == -1);
    CHECK(loaded.warnings.size() == 2);
}

TEST_CASE("textures are resolved from the scene's folder and loaded once", "[loader]") {
    fs::path root = tempFolder("textures");
    writePng(root / "data" / "image" / "board.png");
    fs::path sceneFile = root / "data" / "scenes" / "board scene.xml";
    std::string xml = rootScene(block(
        primitive("cube", "<texture file=\"/course/cs123/data/image/board.png\" u=\"1\" v=\"1\"/>") +
        primitive("sphere", "<texture file=\"..\\image\\board.png\"/><bumpmap file=\"image/board.png\"/>")));
    writeText(sceneFile, xml);

    SECTION("loaded") {
        Loaded loaded;
        LoadOptions options;
        options.warn = [&loaded](const std::string& w) { loaded.warnings.push_back(w); };
        loaded.scene = ray::loadScene(sceneFile, options);
        const Scene& s = loaded.scene;
        CHECK(loaded.warnings.empty());
        REQUIRE(s.images.size() == 1);
        REQUIRE(s.imageFiles.size() == 1);
        CHECK(fs::equivalent(s.imageFiles[0], root / "data" / "image" / "board.png"));
        CHECK(s.images[0].width == 2);
        CHECK(s.images[0].height == 1);
        CHECK(s.materials[0].texture.image == 0);
        CHECK(s.materials[1].texture.image == 0);
        CHECK(s.materials[1].bumpMap.image == 0);
        CHECK(s.sourceFile == sceneFile);
    }
    SECTION("not loaded: resolved and indexed, with an empty image") {
        LoadOptions options;
        options.loadImages = false;
        Scene s = ray::loadScene(sceneFile, options);
        REQUIRE(s.imageFiles.size() == 1);
        REQUIRE(s.images.size() == 1);
        CHECK(s.images[0].empty());
        CHECK(s.materials[0].texture.image == 0);
    }
    fs::remove_all(root);
}

TEST_CASE("a missing texture is a warning that says where it looked", "[loader]") {
    fs::path root = tempFolder("missing");
    fs::path sceneFile = root / "scenes" / "s.xml";
    std::string xml = rootScene(block(primitive("cube", "\n<texture file=\"/course/image/ray-test-gone.png\"/>")));
    Loaded loaded = load(xml, {}, sceneFile);
    REQUIRE(loaded.warnings.size() == 1);
    const std::string& w = loaded.warnings[0];
    CHECK_THAT(w, Contains(at(xml, "<texture", sceneFile.string()) + "warning: texture file '/course/image/ray-test-gone.png' not found"));
    CHECK_THAT(w, Contains((root / "scenes").string()));
    CHECK_THAT(w, Contains("keeps its material colors"));
    CHECK(loaded.scene.materials[0].texture.image == -1);
    CHECK(loaded.scene.images.empty());

    // One warning per file, however many surfaces name it.
    std::string twice = rootScene(block(primitive("cube", "<texture file=\"ray-test-gone.png\"/>") +
                                        primitive("cube", "<bumpmap file=\"ray-test-gone.png\"/>")));
    CHECK(load(twice, {}, sceneFile).warnings.size() == 1);
    fs::remove_all(root);
}

TEST_CASE("a texture that does not decode is a warning, like a missing one", "[loader]") {
    fs::path root = tempFolder("undecodable");
    writeText(root / "bad.png", "this is not a PNG");
    std::string xml = rootScene(block(primitive("cube", "<texture file=\"bad.png\"/>") +
                                      primitive("cube", "<texture file=\"bad.png\"/>")));
    Loaded loaded = load(xml, {}, root / "s.xml");
    CHECK(loaded.warnings.size() == 1);  // once per file
    CHECK(loaded.scene.materials[0].texture.image == -1);
    CHECK(loaded.scene.materials[1].texture.image == -1);
    CHECK(loaded.scene.images.empty());
    fs::remove_all(root);
}

TEST_CASE("meshes are resolved and deduplicated, a missing mesh is an error", "[loader]") {
    fs::path root = tempFolder("meshes");
    writeText(root / "mesh" / "thing.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fs::path sceneFile = root / "scenes" / "s.xml";
    std::string found = rootScene(block("<object type=\"primitive\" name=\"mesh\" meshfile=\"/course/data/mesh/thing.obj\"/>"
                                        "<object type=\"primitive\" name=\"mesh\" filename=\"mesh/thing.obj\"/>" + primitive()));
    Scene s = load(found, {}, sceneFile).scene;
    REQUIRE(s.meshFiles.size() == 1);
    CHECK(fs::equivalent(s.meshFiles[0], root / "mesh" / "thing.obj"));
    CHECK(s.primitives[0].type == ray::PrimitiveType::Mesh);
    CHECK(s.primitives[0].mesh == 0);
    CHECK(s.primitives[1].mesh == 0);
    CHECK(s.primitives[2].mesh == -1);

    std::string missing = rootScene(block("\n<object type=\"primitive\" name=\"mesh\" meshfile=\"mesh/dragon.obj\"/>"));
    std::string error = errorOf(missing, {}, sceneFile);
    CHECK_THAT(error, Contains(at(missing, "dragon", sceneFile.string()) + "error: mesh file 'mesh/dragon.obj' not found"));
    CHECK_THAT(errorOf(rootScene(block("<object type=\"primitive\" name=\"mesh\"/>"))), Contains("needs its OBJ file"));
    fs::remove_all(root);
}

// ---------------------------------------------------------------------------------------
// Bad input

TEST_CASE("malformed XML is an error with its line", "[loader]") {
    std::string error = errorOf("<scenefile>\n<globaldata>\n</scenefile>\n");
    CHECK_THAT(error, Contains("test.xml:2: error: malformed XML: <globaldata> is not closed"));
    CHECK_THAT(errorOf("<scenefile>\n<pos x=1/>\n</scenefile>"),
               Contains("test.xml:2: error: malformed XML: an attribute of <pos> is malformed"));
    CHECK_THAT(errorOf(""), Contains("test.xml: error: the file is empty"));
    CHECK_THAT(errorOf("<scene/>"), Contains("test.xml:1: error: the root element is <scene>"));
    CHECK_THAT(errorOf("<!-- only a comment -->"), Contains("test.xml: error: the file has no XML element"));
    CHECK_THAT(errorOf("<scenefile>\n<globaldata>\n"),
               Contains("test.xml:2: error: malformed XML: <globaldata> is not closed (the file ends first)"));
    CHECK_THAT(errorOf(rootScene(block("<texture file=\"a&b.png\"/>"))),
               Contains("malformed XML: an attribute of <texture> has a bare '&' (write & as &amp;)"));
    CHECK_THAT(errorOf("<scenefile>\n<!-- caf\xE9 -->\n</scenefile>"),
               Contains("test.xml:2: error: malformed XML: byte 0xE9 is not UTF-8 text"));
}

TEST_CASE("XML the old parser took still loads: \"--\" in comments, text after the root", "[loader]") {
    const std::string xml = "<!-- render with --no-dof -- or not --->\n" +
                            rootScene(block("<!-- --course-meshes -->" + primitive())) + "trailing text";
    Loaded loaded = load(xml);
    CHECK(loaded.scene.primitives.size() == 1);
    CHECK(loaded.warnings.empty());
}

TEST_CASE("a scene file is read in pieces: one larger than a piece loads whole", "[loader]") {
    // Over 1 MiB, the size of each piece read, and lines counted across the pieces.
    std::string blocks;
    for (int i = 0; i < 12000; ++i)
        blocks += block("<translate x=\"" + std::to_string(i) + "\" y=\"0\" z=\"0\"/>" + primitive());
    const std::string xml = rootScene(blocks + "<bogus/>");
    REQUIRE(xml.size() > (1u << 20));
    fs::path file = tempFolder("pieces") / "big.xml";
    writeText(file, xml);
    std::vector<std::string> warnings;
    LoadOptions options;
    options.warn = [&](const std::string& w) { warnings.push_back(w); };
    Scene scene = ray::loadScene(file, options);
    REQUIRE(scene.primitives.size() == 12000);
    CHECK(scene.primitives.back().objectToWorld.m[0][3] == 11999);
    REQUIRE(warnings.size() == 1);
    CHECK_THAT(warnings[0], Contains(at(xml, "<bogus/>", file.string()) + "warning: unknown element <bogus>"));
    fs::remove_all(file.parent_path());
}

TEST_CASE("numbers: plain decimals and what only strtod reads give the same values", "[loader]") {
    auto x = [](const std::string& value) {
        return load(rootScene(block("<translate x=\"" + value + "\" y=\"0\" z=\"0\"/>" + primitive())))
            .scene.primitives[0]
            .objectToWorld.m[0][3];
    };
    CHECK(x("1.5") == 1.5);
    CHECK(x("-3.65636") == std::strtod("-3.65636", nullptr));
    CHECK(x("0.1") == 0.1);
    CHECK(x("1.") == 1);
    CHECK(x(".5") == 0.5);
    CHECK(x("-.25") == -0.25);
    CHECK(x("+2") == 2);
    CHECK(x(" 2 ") == 2);
    CHECK(x("1e3") == 1000);
    CHECK(x("0x10") == 16);
    CHECK(x("12345678901234567890.5") == std::strtod("12345678901234567890.5", nullptr));
    CHECK(x("0.00000000000000000000000123") == std::strtod("0.00000000000000000000000123", nullptr));
    CHECK(x("9007199254740993") == std::strtod("9007199254740993", nullptr));  // 2^53 + 1
}

TEST_CASE("a stray '=' before a number is read past, with a warning", "[loader]") {
    std::vector<std::string> warnings;
    ray::LoadOptions options;
    options.warn = [&](const std::string& w) { warnings.push_back(w); };
    ray::Scene scene = ray::loadSceneFromText(rootScene(block("<translate x=\"=1.5\" y=\"0\" z=\"0\"/>" + primitive())), "stray.xml", options);
    REQUIRE(warnings.size() == 1);
    CHECK_THAT(warnings[0], Contains("stray '='"));
    REQUIRE(scene.primitives.size() == 1);
    CHECK(scene.primitives[0].objectToWorld.m[0][3] == 1.5);
    options.strict = true;
    CHECK_THROWS_AS(ray::loadSceneFromText(rootScene(block("<translate x=\"=1.5\" y=\"0\" z=\"0\"/>" + primitive())), "stray.xml", options), ray::InputError);
}

TEST_CASE("a value that is not a number is an error", "[loader]") {
    std::string xml = rootScene(block("\n<translate x=\"1\" y=\"two\" z=\"3\"/>" + primitive()));
    std::string error = errorOf(xml);
    CHECK_THAT(error, Contains(at(xml, "two") + "error: 'two' is not a number (attribute 'y' of <translate>)"));
    CHECK_THAT(errorOf(rootScene(block("<translate x=\"1\" y=\"2\" z=\"3m\"/>"))), Contains("'3m' is not a number"));
    CHECK_THAT(errorOf(rootScene(block("<translate x=\"nan\" y=\"2\" z=\"3\"/>"))), Contains("not a finite number"));
    CHECK_THAT(errorOf(rootScene(block("<translate x=\"inf\" y=\"2\" z=\"3\"/>"))), Contains("not a finite number"));
    CHECK_THAT(errorOf(rootScene(block("<translate x=\"1e999\" y=\"2\" z=\"3\"/>"))), Contains("not a finite number"));
    // Surrounding blanks are fine.
    Scene s = load(rootScene(block("<translate x=\" 1 \" y=\"2\t\" z=\"-3e0\"/>" + primitive()))).scene;
    CHECK(near(s.primitives[0].objectToWorld.transformPoint({0, 0, 0}), {1, 2, -3}));
}

TEST_CASE("an empty numeric attribute reads as 0 with a warning", "[loader]") {
    std::string xml = rootScene(block("\n<translate x=\"1\" y=\"2\" z=\"\"/>" + primitive()));
    Loaded loaded = load(xml);
    CHECK(near(loaded.scene.primitives[0].objectToWorld.transformPoint({0, 0, 0}), {1, 2, 0}));
    REQUIRE(loaded.warnings.size() == 1);
    CHECK_THAT(loaded.warnings[0], Contains(at(xml, "<translate") + "warning: empty attribute 'z' of <translate> reads as 0"));
}

TEST_CASE("an unknown element or attribute is a warning and is ignored", "[loader]") {
    std::string xml = rootScene(block(primitive("cube", "\n<shader/><diffuse r=\"0\" g=\"1\" b=\"0\"/>") +
                                      "<object type=\"primitive\" name=\"sphere\" color=\"red\"/>"),
                                "<physics rate=\"60\"/>\n");
    Loaded loaded = load(xml);
    REQUIRE(loaded.warnings.size() == 3);
    CHECK_THAT(loaded.warnings[0], Contains(at(xml, "<physics") + "warning: unknown element <physics>"));
    CHECK_THAT(loaded.warnings[1], Contains(at(xml, "<shader") + "warning: unknown element <shader>"));
    CHECK_THAT(loaded.warnings[2], Contains(at(xml, "color=") + "warning: unknown attribute 'color'"));
    CHECK(loaded.scene.primitives.size() == 2);
    CHECK(loaded.scene.materials[0].diffuse == Vec3(0, 1, 0));
}

TEST_CASE("containers take no attributes", "[loader]") {
    std::string xml = rootScene("<transblock\nhidden=\"yes\">" + primitive() + "</transblock>");
    Loaded loaded = load(xml);
    REQUIRE(loaded.warnings.size() == 1);
    CHECK_THAT(loaded.warnings[0], Contains(at(xml, "<transblock") + "warning: unknown attribute 'hidden' of <transblock>"));
}

TEST_CASE("strict turns every warning into an error", "[loader]") {
    std::string emptyValue = rootScene(block("<translate x=\"1\" y=\"2\" z=\"\"/>" + primitive()));
    std::string unknownElement = rootScene(block(primitive()), "<physics/>");
    std::string missingTexture = rootScene(block(primitive("cube", "<texture file=\"ray-test-gone.png\"/>")));
    for (const std::string& xml : {emptyValue, unknownElement, missingTexture}) {
        CHECK(errorOf(xml).empty());
        CHECK_THAT(errorOf(xml, strictOptions()), Contains("test.xml:") && Contains(": error: "));
    }
    CHECK(errorOf(rootScene(block(primitive())), strictOptions()).empty());
}

TEST_CASE("warnings go to the callback, complete", "[loader]") {
    std::vector<std::string> seen;
    LoadOptions options;
    options.warn = [&seen](const std::string& w) { seen.push_back(w); };
    ray::loadSceneFromText(rootScene("", "<extra/>"), "dir/scene.xml", options);
    REQUIRE(seen.size() == 1);
    CHECK(seen[0].rfind("dir/scene.xml:2: warning: unknown element <extra>", 0) == 0);
}

TEST_CASE("a scene file that cannot be read is an error naming it", "[loader]") {
    try {
        ray::loadScene("/nonexistent/folder/scene.xml");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(), Contains("/nonexistent/folder/scene.xml: error: cannot open the scene file"));
    }
}

// ---------------------------------------------------------------------------------------
// File search (SPEC §1)

TEST_CASE("file search: the path as given, relative to the scene folder", "[loader]") {
    fs::path root = tempFolder("search_given");
    writeText(root / "scenes" / "tex" / "a.png", "x");
    writeText(root / "abs.png", "x");
    ray::FileSearch search{{}, root / "scenes"};
    CHECK(search.resolve("tex/a.png") == root / "scenes" / "tex" / "a.png");
    CHECK(search.resolve("tex\\a.png") == root / "scenes" / "tex" / "a.png");
    CHECK(search.resolve((root / "abs.png").string()) == root / "abs.png");
    CHECK_FALSE(search.resolve(""));
    CHECK_FALSE(search.resolve("tex"));  // a folder is not a file
    fs::remove_all(root);
}

TEST_CASE("file search: trailing parts under each root, longest first", "[loader]") {
    fs::path root = tempFolder("search_trailing");
    fs::path scenes = root / "a" / "b" / "scenes";
    fs::create_directories(scenes);
    writeText(root / "a" / "image" / "board.png", "x");
    writeText(root / "a" / "board.png", "x");
    ray::FileSearch search{{}, scenes};
    // Under root a: image/board.png (longer) wins over board.png.
    CHECK(search.resolve("/course/cs123/data/image/board.png") == root / "a" / "image" / "board.png");
    // Windows paths: backslashes and a drive letter.
    CHECK(search.resolve("C:\\course\\data\\image\\board.png") == root / "a" / "image" / "board.png");
    CHECK(search.resolve("D:board.png") == root / "a" / "board.png");
    // The scene folder comes before its ancestors.
    writeText(scenes / "board.png", "x");
    CHECK(search.resolve("/course/cs123/data/image/board.png") == scenes / "board.png");
    fs::remove_all(root);
}

TEST_CASE("file search: user roots first, then the scene folder and three ancestors", "[loader]") {
    fs::path root = tempFolder("search_roots");
    fs::path scenes = root / "1" / "2" / "3" / "4";
    fs::create_directories(scenes);
    writeText(root / "far.png", "x");          // the 4th ancestor: not searched
    writeText(root / "1" / "near.png", "x");  // the 3rd ancestor: searched
    writeText(root / "user" / "near.png", "x");
    ray::FileSearch plain{{}, scenes};
    CHECK_FALSE(plain.resolve("/x/far.png"));
    CHECK(plain.resolve("/x/near.png") == root / "1" / "near.png");
    ray::FileSearch withUser{{root / "user"}, scenes};
    CHECK(withUser.resolve("/x/near.png") == root / "user" / "near.png");

    std::vector<fs::path> roots = withUser.searchRoots();
    REQUIRE(roots.size() == 5);
    CHECK(roots[0] == root / "user");
    CHECK(roots[1] == scenes);
    CHECK(roots[4] == root / "1");

    std::vector<fs::path> tried;
    CHECK_FALSE(plain.resolve("/x/y/none.png", &tried));
    CHECK(tried.front() == fs::path("/x/y/none.png"));
    CHECK(std::find(tried.begin(), tried.end(), scenes / "x" / "y" / "none.png") != tried.end());
    CHECK(std::find(tried.begin(), tried.end(), root / "1" / "none.png") != tried.end());
    fs::remove_all(root);
}

TEST_CASE("file search: a relative scene folder, and .. never climbs out of a root", "[loader]") {
    ray::FileSearch search{{}, ""};
    std::vector<fs::path> roots = search.searchRoots();
    REQUIRE_FALSE(roots.empty());
    CHECK(roots[0] == fs::current_path());

    std::vector<fs::path> tried;
    search.resolve("../../secret/x.png", &tried);
    for (size_t i = 1; i < tried.size(); ++i) CHECK(tried[i].string().find("..") == std::string::npos);
}

TEST_CASE("RAY_SEARCH_PATH lists folders separated by ':'", "[loader]") {
    ::setenv("RAY_SEARCH_PATH", "/a:/b/c::rel", 1);
    std::vector<fs::path> paths = ray::searchPathsFromEnvironment();
    ::unsetenv("RAY_SEARCH_PATH");
    REQUIRE(paths.size() == 3);
    CHECK(paths[0] == "/a");
    CHECK(paths[1] == "/b/c");
    CHECK(paths[2] == "rel");
    CHECK(ray::searchPathsFromEnvironment().empty());
}

// ---------------------------------------------------------------------------------------
// Constructive solid geometry (scene/csg.h)

namespace {

std::string csg(const std::string& operation, const std::string& operands) {
    return "<object type=\"csg\" operation=\"" + operation + "\">\n" + operands + "</object>\n";
}

}  // namespace

TEST_CASE("a csg object becomes one instance whose operands stay out of the primitive list", "[loader][csg]") {
    Loaded loaded = load(rootScene(block(csg("union", block(primitive("sphere")) + block(primitive("cube")))) +
                                   block(primitive("cone"))));
    CHECK(loaded.warnings.empty());
    REQUIRE(loaded.scene.primitives.size() == 2);
    CHECK(loaded.scene.primitives[0].type == ray::PrimitiveType::Csg);
    CHECK(loaded.scene.csgOperands.size() == 2);
}

TEST_CASE("bad csg objects are errors at their line", "[loader][csg]") {
    std::string one = rootScene(block(csg("union", block(primitive()))));
    CHECK_THAT(errorOf(one), Contains(at(one, "type=\"csg\"") + "error: a csg object needs two or more operands but has 1"));
    std::string unknown = rootScene(block(csg("xor", block(primitive()) + block(primitive()))));
    CHECK_THAT(errorOf(unknown), Contains(at(unknown, "type=\"csg\"") + "error: unknown csg operation 'xor'"));
    std::string noOperation = rootScene(block("<object type=\"csg\">" + block(primitive()) + block(primitive()) +
                                              "</object>"));
    CHECK_THAT(errorOf(noOperation), Contains(at(noOperation, "type=\"csg\"") + "error: a csg object needs an operation"));
    std::string torus = rootScene(block(csg("difference", block(primitive()) + block(primitive("torus")))));
    CHECK_THAT(errorOf(torus), Contains(at(torus, "name=\"torus\"") + "error: a torus cannot be an operand"));
    std::string empty = rootScene(block(csg("union", block(primitive()) + "<transblock/>\n")));
    CHECK_THAT(errorOf(empty), Contains(at(empty, "type=\"csg\"") + "error: operand 2 of this csg object is empty"));
    std::string moving = rootScene(block(
        csg("union", block(primitive()) + block("<motion x=\"1\" y=\"0\" z=\"0\"/>" + primitive("sphere")))));
    CHECK_THAT(errorOf(moving), Contains(at(moving, "name=\"sphere\"") + "error: a <motion> inside a csg object"));
    std::string operands;
    for (int i = 0; i < ray::kCsgMaxOperands + 1; ++i) operands += block(primitive("sphere"));
    std::string many = rootScene(block(csg("union", operands)));
    CHECK_THAT(errorOf(many), Contains(at(many, "type=\"csg\"") + "error: this csg object holds 33 primitives"));
    std::string deep = block(primitive()) + block(primitive());
    for (int level = 0; level < ray::kCsgMaxStack; ++level) deep = block(primitive()) + block(csg("union", deep));
    std::string nested = rootScene(block(csg("union", deep)));
    CHECK_THAT(errorOf(nested), Contains(at(nested, "type=\"csg\"") + "error: csg objects nest too deeply"));
}
