// The course's JSON scenefiles (SPEC §7; scene/json_scene_reader.h), rule by rule, and the
// JSON tree under them (scene/json_tree.h).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <fstream>
#include <string>
#include <vector>

#include "scene/json_scene_reader.h"
#include "scene/json_tree.h"
#include "scene/scene_loader.h"
#include "scene_text.h"
#include "test_support.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using ray::InputError;
using ray::LoadOptions;
using ray::Scene;
using ray::Vec3;

namespace {

using Loaded = ray::test::LoadedText;

// Loads JSON text as "scene.json" (or `file`), collecting the warnings.
Loaded load(const std::string& json, LoadOptions options = {}, const fs::path& file = "scene.json") {
    return ray::test::loadText(json, file, std::move(options));
}

// The message of the InputError that loading throws ("" when it loads).
std::string errorOf(const std::string& json, LoadOptions options = {}, const fs::path& file = "scene.json") {
    return ray::test::loadError(json, file, std::move(options));
}

const char* const kGlobals =
    R"("globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5})";
const char* const kCamera =
    R"("cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "heightAngle": 45, "look": [0, 0, -1]})";

// A scene with the usual globals and camera, and `rest` (",\n  \"groups\": [...]").
std::string scene(const std::string& rest) { return std::string("{\n  ") + kGlobals + ",\n  " + kCamera + rest + "\n}\n"; }

std::string groups(const std::string& list) { return ",\n  \"groups\": [" + list + "]"; }

bool near(const Vec3& a, const Vec3& b) {
    return std::abs(a.x - b.x) < 1e-12 && std::abs(a.y - b.y) < 1e-12 && std::abs(a.z - b.z) < 1e-12;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The tree

TEST_CASE("the JSON tree keeps each value's and each key's offset", "[json]") {
    const std::string text = "\xEF\xBB\xBF{\"a\": [1, \"x\"],\n \"b\" :{\"c\":null}}";
    const ray::JsonTree tree = ray::JsonTree::parse(text, 10);
    const ray::JsonValue root = tree.root();
    REQUIRE(root.isObject());
    CHECK(root.offset() == 3);
    const ray::JsonValue a = root.first();
    CHECK(a.key() == "a");
    CHECK(a.keyOffset() == text.find("\"a\""));
    CHECK(a.offset() == text.find('['));
    CHECK(a.first().number() == 1);
    CHECK(a.first().next().string() == "x");
    CHECK(a.first().next().offset() == text.find("\"x\""));
    const ray::JsonValue b = a.next();
    CHECK(b.keyOffset() == text.find("\"b\""));
    CHECK(b.offset() == text.find("{\"c\""));
    CHECK(b.first().kind() == ray::JsonKind::Null);
    const ray::JsonLines lines(text);
    CHECK(lines.line(b.keyOffset()) == 2);
    CHECK(lines.column(b.keyOffset()) == 2);
    CHECK(lines.column(root.offset()) == 1);  // the byte-order mark is no character
}

TEST_CASE("the JSON tree refuses what is not JSON, with the byte where", "[json]") {
    auto errorAt = [](const std::string& text, int depth = 64) -> std::pair<ray::JsonError::Kind, size_t> {
        try {
            ray::JsonTree::parse(text, depth);
        } catch (const ray::JsonError& e) {
            return {e.kind, e.offset};
        }
        return {ray::JsonError::Kind::Empty, size_t(-1)};
    };
    CHECK(errorAt(" \n ").first == ray::JsonError::Kind::Empty);
    CHECK(errorAt("{\"a\": [1, 2,]}") == std::make_pair(ray::JsonError::Kind::Malformed, size_t(12)));
    CHECK(errorAt("{\"a\": 1} x").first == ray::JsonError::Kind::Malformed);
    CHECK(errorAt("{\"a\": 1e400}").first == ray::JsonError::Kind::Malformed);
    CHECK(errorAt("[[[[1]]]]", 3).first == ray::JsonError::Kind::TooDeep);
    CHECK(errorAt("\xFF\xFE{\0}").first == ray::JsonError::Kind::Malformed);
    CHECK(errorAt("{\"a\": \"\xC3\x28\"}").first == ray::JsonError::Kind::Malformed);  // not UTF-8
    CHECK(errorAt(std::string(100000, '['), ray::kMaxJsonDepth).first == ray::JsonError::Kind::TooDeep);
}

// ---------------------------------------------------------------------------------------
// The format's rules

TEST_CASE("a JSON scene loads into the same scene as its XML", "[json]") {
    const std::string json = scene(groups(R"(
    {"translate": [1, 2, 3], "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}]},
    {"scale": [2, 2, 2], "translate": [0, 1, 0], "rotate": [0, 1, 0, 90],
     "primitives": [{"type": "sphere", "diffuse": [1, 0, 0], "shininess": 20}]})"));
    const std::string xml = R"(<scenefile>
  <globaldata><ambientcoeff v="0.5"/><diffusecoeff v="0.5"/><specularcoeff v="0.5"/><transparentcoeff v="0"/></globaldata>
  <cameradata><pos x="0" y="0" z="5"/><look x="0" y="0" z="-1"/><up x="0" y="1" z="0"/><heightangle v="45"/></cameradata>
  <lightdata><type v="point"/><color r="1" g="1" b="1"/><function v1="1" v2="0" v3="0"/><position x="1" y="2" z="3"/></lightdata>
  <object type="tree" name="root"><transblock>
    <translate x="0" y="1" z="0"/><rotate x="0" y="1" z="0" angle="90"/><scale x="2" y="2" z="2"/>
    <object type="primitive" name="sphere"><diffuse r="1" g="0" b="0"/><shininess v="20"/></object>
  </transblock></object>
</scenefile>)";
    const Scene fromJson = load(json).scene;
    const Scene fromXml = ray::loadSceneFromText(xml, "scene.xml");
    REQUIRE(fromJson.primitives.size() == 1);
    REQUIRE(fromJson.lights.size() == 1);
    CHECK(near(fromJson.lights[0].position, {1, 2, 3}));
    CHECK(fromJson.globals.kt == 0);  // transparentCoeff left out: 0
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            CHECK(fromJson.primitives[0].objectToWorld.m[r][c] == fromXml.primitives[0].objectToWorld.m[r][c]);
    CHECK(fromJson.materials[0].diffuse.y == 0);
    CHECK(fromJson.materials[0].shininess == 20);
    CHECK(fromJson.camera == fromXml.camera);
}

TEST_CASE("a JSON group's transforms apply as T R S Matrix whatever the order of their keys", "[json]") {
    auto placed = [](const std::string& group) {
        return load(scene(groups(group))).scene.primitives.at(0).objectToWorld.transformPoint({1, 0, 0});
    };
    const Vec3 inOrder = placed(R"({"translate": [5, 0, 0], "rotate": [0, 0, 1, 90], "scale": [2, 3, 4],
        "matrix": [[1, 0, 0, 0], [0, 1, 0, 1], [0, 0, 1, 0], [0, 0, 0, 1]], "primitives": [{"type": "cube"}]})");
    const Vec3 reversed = placed(R"({"matrix": [[1, 0, 0, 0], [0, 1, 0, 1], [0, 0, 1, 0], [0, 0, 0, 1]],
        "scale": [2, 3, 4], "rotate": [0, 0, 1, 90], "translate": [5, 0, 0], "primitives": [{"type": "cube"}]})");
    // (1,0,0): matrix → (1,1,0), scale → (2,3,0), rotate 90° about z → (−3,2,0), translate → (2,2,0)
    CHECK(near(inOrder, {2, 2, 0}));
    CHECK(near(reversed, inOrder));
}

TEST_CASE("JSON lights are placed by their groups' transforms, templates' once per placement", "[json]") {
    const std::string json = scene(R"(,
  "groups": [
    {"translate": [0, 10, 0], "groups": [{"name": "lamp"}]},
    {"rotate": [0, 0, 1, 90], "lights": [{"type": "directional", "color": [1, 1, 1], "direction": [1, 0, 0]}]},
    {"translate": [5, 0, 0], "groups": [{"name": "lamp"}]}
  ],
  "templateGroups": [
    {"name": "lamp", "translate": [1, 0, 0],
     "lights": [{"type": "spot", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0], "direction": [0, -1, 0],
                 "angle": 30, "penumbra": 5}],
     "primitives": [{"type": "cone"}]}
  ])");
    const Scene s = load(json).scene;
    REQUIRE(s.lights.size() == 3);
    CHECK(s.lights[0].type == ray::LightType::Spot);
    CHECK(near(s.lights[0].position, {1, 10, 0}));
    CHECK(s.lights[0].angleDegrees == 30);
    CHECK(s.lights[1].type == ray::LightType::Directional);
    CHECK(near(s.lights[1].direction, {0, 1, 0}));
    CHECK(near(s.lights[2].position, {6, 0, 0}));
    CHECK(s.primitives.size() == 2);  // the template's cone, placed twice
}

TEST_CASE("a JSON template may be named before it is defined, and only a template's name places it", "[json]") {
    const std::string json = scene(R"(,
  "templateGroups": [
    {"name": "pair", "groups": [{"name": "ball"}, {"translate": [2, 0, 0], "groups": [{"name": "ball"}]}]},
    {"name": "ball", "primitives": [{"type": "sphere"}]}
  ],
  "groups": [{"name": "pair"}, {"name": "not a template", "primitives": [{"type": "cube"}]}])");
    const Loaded loaded = load(json);
    CHECK(loaded.scene.primitives.size() == 3);
    CHECK(loaded.warnings.empty());
}

TEST_CASE("a JSON group named as a template is the template: its other keys warn and are ignored", "[json]") {
    const Loaded loaded = load(scene(R"(,
  "templateGroups": [{"name": "T", "primitives": [{"type": "cube"}]}],
  "groups": [{"name": "T", "translate": [9, 9, 9]}])"));
    REQUIRE(loaded.scene.primitives.size() == 1);
    CHECK(near(loaded.scene.primitives[0].objectToWorld.transformPoint({0, 0, 0}), {0, 0, 0}));
    REQUIRE(loaded.warnings.size() == 1);
    CHECK_THAT(loaded.warnings[0], StartsWith("scene.json:5:41: warning: \"translate\" in groups[0] is ignored"));
}

TEST_CASE("JSON scene errors name line, column and the place in the file's terms", "[json]") {
    const std::string json = scene(groups(R"(
    {"primitives": [{"type": "cube"}]},
    {"primitives": [
      {"type": "sphere", "colour": [1, 0, 0]}]})"));
    CHECK_THAT(errorOf(json), StartsWith("scene.json:7:26: error: unknown key \"colour\" in groups[1].primitives[0] "
                                         "(a primitive has: type, meshFile, ambient, diffuse,"));
}

TEST_CASE("every rule of a JSON scene refuses what the course's reader refuses, in words", "[json]") {
    struct Case {
        std::string json, expected;
    };
    const std::vector<Case> cases = {
        {"{}", "the scene needs \"globalData\" at the top level"},
        {"[1]", "the file must be an object"},
        {std::string("{") + kGlobals + "}", "needs \"cameraData\""},
        {scene(",\n  \"lights\": []"), "unknown key \"lights\" at the top level"},
        {scene(groups(R"({"primitives": [{"type": "torus"}]})")), "a JSON scene has no torus"},
        {scene(groups(R"({"primitives": [{"type": "cube", "diffuse": [1, 0]}]})")),
         "\"diffuse\" in groups[0].primitives[0] must be an array of 3 numbers [r, g, b], not 2 values"},
        {scene(groups(R"({"primitives": [{"type": "cube", "shininess": "high"}]})")), "must be a number, not a string"},
        {scene(groups(R"({"primitives": [{"type": "cube", "shininess": -1}]})")), "shininess must be 0 or more"},
        {scene(groups(R"({"primitives": [{"type": "cube", "textureU": true}]})")), "must be a number, not true or false"},
        {scene(groups(R"({"primitives": [{"type": "cube", "type": "cube"}]})")), "key \"type\" given twice"},
        {scene(groups(R"({"primitives": [{"type": "mesh"}]})")), "a primitive needs \"meshFile\""},
        {scene(groups(R"({"scale": [1, 0, 1], "primitives": [{"type": "cube"}]})")), "zero scale"},
        {scene(groups(R"({"rotate": [0, 0, 0, 10]})")), "rotation axis is zero"},
        {scene(groups(R"({"rotate": [0, 1, 0]})")), "must be an array of 4 numbers [x, y, z, degrees]"},
        {scene(groups(R"({"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]})")), "has 3 rows, not 4"},
        {scene(groups(R"({"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]})")),
         "last row is not [0, 0, 0, 1]"},
        {scene(groups(R"({"lights": [{"type": "point", "color": [1, 1, 1]}]})")), "a light needs \"attenuationCoeff\""},
        {scene(groups(R"({"lights": [{"type": "directional", "color": [1, 1, 1]}]})")), "a light needs \"direction\""},
        {scene(groups(R"({"lights": [{"type": "spot", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0],
           "direction": [0, -1, 0], "angle": 30}]})")),
         "a light needs \"penumbra\""},
        {scene(groups(R"({"lights": [{"type": "area", "color": [1, 1, 1]}]})")), "no area lights"},
        {std::string("{") + kGlobals + R"(, "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "heightAngle": 45}})",
         "the camera has neither \"look\" nor \"focus\""},
        {std::string("{") + kGlobals +
             R"(, "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "heightAngle": 45, "look": [0, 0, -1], "focus": [0, 0, 0]}})",
         "the camera has both"},
        {std::string("{") + kGlobals +
             R"(, "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "heightAngle": 180, "look": [0, 0, -1]}})",
         "heightAngle"},
        {scene(R"(, "templateGroups": [{"primitives": []}])"), "a group needs \"name\" in templateGroups[0]"},
        {scene(R"(, "templateGroups": [{"name": "a"}, {"name": "a"}])"), "a second template named \"a\""},
        {scene(R"(, "templateGroups": [{"name": "root"}])"), "a template named \"root\""},
        {scene(R"(, "templateGroups": [{"name": "a", "groups": [{"name": "a"}]}])"),
         "template \"a\" contains itself: \"a\" -> \"a\""},
        {scene(R"(, "templateGroups": [{"name": "a", "groups": [{"name": "b"}]}, {"name": "b", "groups": [{"groups": [{"name": "a"}]}]}])"),
         "contains itself: \"a\" -> \"b\" -> \"a\""},
        {scene(",\n  \"groups\": {}"), "\"groups\" at the top level must be an array"},
        {"{\"a\": 1,}", "malformed JSON"},
        {"", "the file is empty"},
    };
    for (const Case& c : cases) {
        INFO(c.json);
        CHECK_THAT(errorOf(c.json), Contains(c.expected));
        CHECK_THAT(errorOf(c.json), StartsWith("scene.json:"));
    }
}

TEST_CASE("hostile JSON scenes are refused quickly and without memory a small file cannot justify", "[json]") {
    // Deep nesting, a long array where three numbers go, a huge number, a 1 MB string, a
    // template placing itself: each an error, never a crash or a hang.
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    CHECK_THAT(errorOf(deep), Contains("nested deeper than"));
    std::string longArray = "[";
    for (int i = 0; i < 1000000; ++i) longArray += i ? ",0" : "0";
    longArray += "]";
    CHECK_THAT(errorOf(scene(groups("{\"translate\": " + longArray + "}"))), Contains("not 1000000 values"));
    CHECK_THAT(errorOf(scene(groups(R"({"translate": [1e999, 0, 0]})"))), Contains("malformed JSON"));
    CHECK_THAT(errorOf(scene(groups("{\"name\": \"" + std::string(1 << 20, 'x') + "\", \"colour\": 1}"))),
               Contains("unknown key \"colour\" in groups[0]"));
    // Templates that place their lights 2^40 times: refused from the count, before any is made.
    std::string templates = R"({"name": "t0", "lights": [{"type": "directional", "color": [1, 1, 1], "direction": [0, -1, 0]}]})";
    for (int i = 1; i <= 40; ++i)
        templates += ", {\"name\": \"t" + std::to_string(i) + "\", \"groups\": [{\"name\": \"t" + std::to_string(i - 1) +
                     "\"}, {\"name\": \"t" + std::to_string(i - 1) + "\"}]}";
    CHECK_THAT(errorOf(scene(",\n  \"templateGroups\": [" + templates + "],\n  \"groups\": [{\"name\": \"t40\"}]")),
               Contains("more than the 65536 ray takes"));
}

TEST_CASE("the format of a scene comes from its first character, else its extension", "[json]") {
    CHECK(ray::sceneFormatOf("a.json", "<scenefile>") == ray::SceneFormat::Xml);
    CHECK(ray::sceneFormatOf("a.XML", "{") == ray::SceneFormat::Json);
    CHECK(ray::sceneFormatOf("a.scene", "\xEF\xBB\xBF  \n{") == ray::SceneFormat::Json);
    CHECK(ray::sceneFormatOf("a.scene", "<?xml") == ray::SceneFormat::Xml);
    CHECK(ray::sceneFormatOf("scene", "") == ray::SceneFormat::Xml);
    CHECK(ray::sceneFormatOf("scene.JSON", "") == ray::SceneFormat::Json);
    CHECK(ray::sceneFormatOf("scene.json", "oops") == ray::SceneFormat::Json);
    // A JSON string under the API's default name "scene.xml", and one in a .txt file.
    const std::string json = scene(groups(R"({"primitives": [{"type": "cube"}]})"));
    CHECK(load(json, {}, "scene.xml").scene.primitives.size() == 1);
    const fs::path file = ray::test::outputDir() / "json_scene.txt";
    std::ofstream(file) << json;
    CHECK(ray::loadScene(file).primitives.size() == 1);
    CHECK_THAT(errorOf("", {}, "empty.json"), Contains("empty.json: error: the file is empty; give a CS1230 JSON scene"));
}

TEST_CASE("JSON paths are relative to the folder above the scene's, then searched as SPEC 1 says", "[json]") {
    const fs::path root = ray::test::outputDir() / "json_paths";
    fs::remove_all(root);
    fs::create_directories(root / "project" / "scenes");
    fs::create_directories(root / "project" / "textures");
    fs::create_directories(root / "project" / "meshes");
    fs::copy_file(ray::test::scenesDir() / "textures" / "checker.png",
                  root / "project" / "textures" / "board.png", fs::copy_options::overwrite_existing);
    {
        std::ofstream mesh(root / "project" / "meshes" / "tri.obj");
        mesh << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    }
    const fs::path file = root / "project" / "scenes" / "s.json";
    {
        std::ofstream out(file);
        out << scene(groups(R"({"primitives": [
            {"type": "cube", "textureFile": "textures/board.png", "textureU": 2, "blend": 1},
            {"type": "mesh", "meshFile": "meshes/tri.obj"},
            {"type": "cube", "textureFile": "/course/cs1230/textures/board.png"}]})"));
    }
    std::vector<std::string> warnings;
    LoadOptions options;
    options.warn = [&](const std::string& w) { warnings.push_back(w); };
    const Scene s = ray::loadScene(file, options);
    REQUIRE(s.imageFiles.size() == 1);
    CHECK(fs::equivalent(s.imageFiles[0], root / "project" / "textures" / "board.png"));
    CHECK(s.materials[0].texture.repeatU == 2);
    CHECK(s.materials[0].texture.repeatV == 1);
    CHECK(s.meshFiles.size() == 1);
    CHECK(warnings.empty());  // the course path: found by the search, textures/board.png under project/
    CHECK(s.materials[2].texture.image == 0);

    std::ofstream(file) << scene(groups(R"({"primitives": [{"type": "mesh", "meshFile": "meshes/dragon.obj"}]})"));
    try {
        ray::loadScene(file, options);
        FAIL("a missing mesh loaded");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(), Contains("s.json:4:59: error: mesh file 'meshes/dragon.obj' not found"));
    }
}

TEST_CASE("a JSON scene document saves as its text; one made from nothing is written whole", "[json]") {
    const std::string text = scene(groups(R"({"primitives": [{"type": "cube"}]})"));
    ray::SceneDocument document = ray::loadSceneDocumentFromText(text, "scene.json");
    CHECK(document.format == ray::SceneFormat::Json);
    CHECK(ray::documentToText(document, ray::Resources{}, "scene.json") == text);  // test_json_save.cpp: edits
    const ray::SceneDocument copy = document;
    CHECK(copy.format == ray::SceneFormat::Json);
    ray::SceneDocument fromNothing;  // json_writer.h writes it
    fromNothing.format = ray::SceneFormat::Json;
    CHECK_THAT(ray::documentToText(fromNothing, ray::Resources{}, "scene.json"), Contains("\"globalData\": {"));
}

// ---------------------------------------------------------------------------------------
// The course's 105 JSON scenes (../shared/cs1230)

TEST_CASE("every course JSON scene loads, but the two naming the absent dragon.obj", "[json][corpus]") {
    std::optional<fs::path> shared = ray::test::sharedDir();
    if (!shared || !fs::is_directory(*shared / "cs1230" / "scenefiles")) {
        ray::test::skip("../shared/cs1230 is absent: the course's JSON scenes are not here");
        return;
    }
    const fs::path root = *shared / "cs1230" / "scenefiles";
    std::vector<fs::path> scenes;
    for (const auto& entry : fs::recursive_directory_iterator(root))
        if (entry.path().extension() == ".json") scenes.push_back(entry.path());
    std::sort(scenes.begin(), scenes.end());
    REQUIRE(scenes.size() == 105);
    size_t loaded = 0, primitives = 0;
    std::vector<std::string> failures;
    for (const fs::path& file : scenes) {
        LoadOptions options;
        options.loadImages = false;  // the images' decoding is not the format's
        options.warn = [](const std::string&) {};
        try {
            primitives += ray::loadScene(file, options).primitives.size();
            ++loaded;
        } catch (const InputError& e) {
            failures.push_back(fs::relative(file, root).string() + ": " + e.what());
        }
    }
    CHECK(loaded == 103);
    REQUIRE(failures.size() == 2);
    for (const std::string& failure : failures) {
        INFO(failure);
        CHECK_THAT(failure, Contains("mesh.json:34:27: error: mesh file 'meshes/dragon.obj' not found (looked at "));
        CHECK_THAT(failure, Contains("put the OBJ file there, or name its folder with a search path"));
    }
    CHECK_THAT(failures[0], StartsWith("intersect/extra_credit/mesh.json:"));
    CHECK_THAT(failures[1], StartsWith("lights-camera/extra_credit/mesh.json:"));
    CHECK(primitives > 1000);
}
