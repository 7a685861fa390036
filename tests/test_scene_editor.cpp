// ray view's editor (host/viewer/scene_editor.h): edits checked whole and refused without a
// change, undo and redo by user action, the page's routes of the edit model (/op, /outline,
// /node), saving that loads back to the edited scene.
#include <catch2/catch.hpp>

#include <filesystem>
#include <cstring>
#include <fstream>

#include <unistd.h>

#include "course_json_rules.h"
#include "scene/scene_loader.h"
#include "viewer/folder_files.h"
#include "viewer/new_scene.h"
#include "viewer/scene_editor.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path copyOfShadows(const std::string& name) {
    const fs::path folder = fs::temp_directory_path() / ("ray_scene_editor_" + name + "_" + std::to_string(::getpid()));
    fs::create_directories(folder);
    const fs::path file = folder / "shadows.xml";
    fs::copy_file(ray::test::scenesDir() / "shadows.xml", file, fs::copy_options::overwrite_existing);
    return file;
}

ray::RenderSettings sized(int width, int height) {
    ray::RenderSettings s;
    s.width = width;
    s.height = height;
    return s;
}

}  // namespace

TEST_CASE("SceneEditor: pick names the object, an edit changes its material and can be undone and redone",
          "[viewer][editor]") {
    ray::SceneEditor editor(copyOfShadows("edit"), {});
    const auto before = editor.scene();
    const json picked = editor.pick(before->camera, sized(320, 240), 160, 120);
    REQUIRE(picked["object"].is_number_integer());
    const int id = picked["object"];
    CHECK(picked["path"] == "root/transblock[0]/object[0]");
    CHECK(editor.pick(before->camera, sized(320, 240), 0, 0)["object"].is_null());
    CHECK_THROWS_AS(editor.pick(before->camera, sized(320, 240), 320, 0), ray::EditError);

    editor.edit({{"object", id}, {"material", {{"diffuse", {1, 0, 0}}}}});
    const auto after = editor.scene();
    CHECK(after != before);
    const int instance = picked["instance"];
    CHECK(after->materials[size_t(after->primitives[size_t(instance)].material)].diffuse == ray::Vec3{1, 0, 0});
    CHECK(editor.modified());
    CHECK(editor.canUndo());
    CHECK(editor.objectJson(id)["material"]["diffuse"] == json({1.0, 0.0, 0.0}));

    REQUIRE(editor.undo()["done"]);
    CHECK(editor.scene()->materials[size_t(editor.scene()->primitives[size_t(instance)].material)].diffuse ==
          before->materials[size_t(before->primitives[size_t(instance)].material)].diffuse);
    CHECK_FALSE(editor.modified());
    REQUIRE(editor.redo()["done"]);
    CHECK(editor.objectJson(id)["material"]["diffuse"] == json({1.0, 0.0, 0.0}));
    CHECK_FALSE(editor.redo()["done"]);
}

TEST_CASE("SceneEditor: a bad edit is refused with a message and changes nothing", "[viewer][editor]") {
    ray::SceneEditor editor(copyOfShadows("bad"), {});
    const auto scene = editor.scene();
    const uint64_t version = editor.version();
    auto refused = [&](const json& edit, const std::string& words) {
        INFO(edit.dump());
        try {
            editor.edit(edit);
            FAIL("accepted");
        } catch (const ray::EditError& e) {
            CHECK_THAT(e.what(), Catch::Matchers::Contains(words));
        }
        CHECK(editor.scene() == scene);
        CHECK(editor.version() == version);
        CHECK_FALSE(editor.canUndo());
    };
    refused({{"object", 0}, {"material", {{"diffuse", {-1, 0, 0}}}}}, "diffuse must be 0 or more");
    refused({{"object", 0}, {"material", {{"ior", 0}}}}, "ior");
    refused({{"object", 0}, {"material", {{"blend", 2}}}}, "blend");
    refused({{"object", 0}, {"material", {{"glow", 2}}}}, "no field 'glow'");
    refused(json::parse(R"({"object": 0, "material": {"diffuse": [1, 0, 0]}, "transform": []})"),
            "its material or its transform");
    refused(json::parse(R"({"object": 0})"), "its material or its transform");
    refused({{"object", 0}, {"material", {{"diffuse", {1, 0, 0}}, {"shininess", -1}}}}, "shininess");
    refused({{"object", 99}, {"material", {{"diffuse", {1, 0, 0}}}}}, "object-99 does not exist");
    refused({{"object", 0}, {"transform", {{{"kind", "scale"}, {"v", {0, 1, 1}}}}}}, "scale of 0");
    refused({{"object", 0}, {"transform", {{{"kind", "matrix"}, {"v", {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0}}}}}},
            "the matrix is singular");
    refused({{"object", 0}, {"transform", {{{"kind", "rotate"}, {"v", {0, 0, 0, 30}}}}}}, "axis");
    refused({{"object", 0}, {"transform", {{{"kind", "shear"}, {"v", {1, 1, 1}}}}}}, "translate, rotate, scale or matrix");
    refused({{"light", 3}, {"color", {1, 1, 1}}}, "no light 3");
    refused({{"light", 0}, {"attenuation", {0, 0, 0}}}, "divides by zero");
    refused({{"light", 0}, {"color", {1, 1}}}, "color takes a color, three numbers [r, g, b]");
    refused(json::array(), "JSON object");
}

TEST_CASE("SceneEditor: one user action is one step however quick the edits, transforms and lights, save loads back",
          "[viewer][editor]") {
    const fs::path file = copyOfShadows("save");
    ray::SceneEditor editor(file, {});
    const auto original = editor.scene();
    const ray::Camera view = original->camera;
    // A color dragged across the picker: one action; a move, a light: one each.
    for (double r : {0.2, 0.4, 0.6})
        editor.operate(ray::edit::parseTypedJson(R"({"action": "pick-1", "op": "set", "node": "object-1",
            "fields": {"diffuse": [)" + std::to_string(r) + R"(, 0, 0]}})"), view);
    editor.edit({{"object", 1}, {"transform", {{{"kind", "translate"}, {"v", {-1.8, 0.5, 0}}}}}});
    editor.edit({{"light", 0}, {"color", {0.5, 0.25, 1}}});
    // Quick edits of one thing without an action id are steps of their own (the 1.5 s merge is gone).
    editor.edit({{"object", 2}, {"material", {{"shininess", 3}}}});
    editor.edit({{"object", 2}, {"material", {{"shininess", 4}}}});
    REQUIRE(editor.undo()["done"]);  // shininess 4
    REQUIRE(editor.undo()["done"]);  // shininess 3
    CHECK(editor.objectJson(2)["material"]["shininess"] == 20);
    REQUIRE(editor.undo()["done"]);  // the light
    REQUIRE(editor.undo()["done"]);  // the transform
    const json colors = editor.undo();  // the three colors at once
    CHECK(colors["done"]);
    CHECK(colors["changed"]["tables"] == json::array({"materials"}));
    CHECK_FALSE(editor.canUndo());
    CHECK(editor.objectJson(1)["material"]["diffuse"] == json({0.9, 0.3, 0.3}));  // as the file has it
    REQUIRE(editor.redo()["done"]);
    REQUIRE(editor.redo()["done"]);
    REQUIRE(editor.redo()["done"]);
    CHECK(editor.objectJson(1)["material"]["diffuse"] == json({0.6, 0.0, 0.0}));
    CHECK(editor.objectJson(1)["transform"] == json::parse(R"([{"kind": "translate", "v": [-1.8, 0.5, 0.0]}])"));

    const fs::path saved = editor.save();
    CHECK(fs::equivalent(saved, file));
    CHECK_FALSE(editor.modified());
    const ray::Scene loaded = ray::loadScene(file);
    const ray::Scene& edited = *editor.scene();
    REQUIRE(loaded.primitives.size() == edited.primitives.size());
    for (size_t i = 0; i < loaded.primitives.size(); ++i) {
        CHECK(std::memcmp(loaded.primitives[i].objectToWorld.m, edited.primitives[i].objectToWorld.m,
                          sizeof loaded.primitives[i].objectToWorld.m) == 0);
        CHECK(loaded.materials[size_t(loaded.primitives[i].material)].diffuse ==
              edited.materials[size_t(edited.primitives[i].material)].diffuse);
    }
    CHECK(loaded.lights[0].color == ray::Vec3{0.5, 0.25, 1});
    CHECK(original->lights[0].color != loaded.lights[0].color);

    const fs::path copy = editor.save("copy.xml");
    CHECK(copy == fs::canonical(file.parent_path()) / "copy.xml");
    CHECK(fs::exists(copy));
    CHECK_THROWS_AS(editor.save("copy.txt"), ray::BadFileName);
    CHECK_THROWS_AS(editor.save("copy.xml"), ray::FileExists);  // written above: replaced only when asked
    CHECK(editor.save("copy.xml", true) == copy);
    CHECK_THROWS_AS(editor.save("../copy.xml"), ray::BadFileName);

    // A change on disk: loaded again, the history starts again.
    std::ofstream(file) << std::ifstream(ray::test::scenesDir() / "shadows.xml").rdbuf();
    editor.reload();
    CHECK_FALSE(editor.canUndo());
    CHECK(editor.scene()->lights[0].color == original->lights[0].color);
}

TEST_CASE("SceneEditor: the outline names every node, a node's fields, an operation answers what it changed",
          "[viewer][editor]") {
    ray::SceneEditor editor(copyOfShadows("routes"), {});
    const json outline = editor.outlineJson()["nodes"];
    CHECK(outline[0]["node"] == "camera");
    CHECK(outline[1]["node"] == "globals");
    CHECK(outline[2]["kind"] == "light");
    CHECK(outline[2]["text"] == "point light");
    size_t objects = 0;
    for (const json& node : outline) objects += node["kind"] == "object" ? 1 : 0;
    CHECK(objects == editor.scene()->primitives.size());
    const json sphere = editor.nodeJson("object-2");
    CHECK(sphere["shape"] == "sphere");
    CHECK(sphere["fields"][0]["name"] == "diffuse");
    CHECK(sphere["own_block"] == true);
    const ray::Camera view{{0, 9, 9}, {0, -1, -1}, {0, 1, 0}, 30, 0, 0};
    const json added = editor.operate(ray::edit::parseTypedJson(R"({"op": "add-primitive", "shape": "torus"})"), view);
    CHECK(added["added"].size() == 2);
    CHECK(added["changed"]["outline"] == true);
    const json camera = editor.operate(ray::edit::parseTypedJson(R"({"op": "camera-from-view"})"), view);
    CHECK(camera["changed"]["tables"] == json::array({"camera"}));
    CHECK(editor.nodeJson("camera")["fields"][0]["value"] == json({0.0, 9.0, 9.0}));
    CHECK_THROWS_WITH(editor.nodeJson("object-99"), Catch::Matchers::Contains("object-99 does not exist"));
    CHECK_THROWS_WITH(editor.nodeJson("sphere"), Catch::Matchers::Contains("names no node"));
    // A texture is a file beside the scene: another folder, or a link out of it, is refused.
    const fs::path folder = editor.file().parent_path();
    fs::copy_file(ray::test::scenesDir() / "textures" / "wood.png", folder / "wood.png", fs::copy_options::overwrite_existing);
    std::error_code ignored;
    fs::remove(folder / "outside.png", ignored);
    fs::create_symlink(ray::test::scenesDir() / "textures" / "wood.png", folder / "outside.png");
    editor.operate(ray::edit::parseTypedJson(R"({"op": "set", "node": "object-2", "fields": {"texture": "wood.png"}})"), view);
    for (const char* name : {"../wood.png", "/etc/passwd.png", "outside.png", "none.png"})
        CHECK_THROWS_AS(editor.operate(ray::edit::parseTypedJson(std::string(R"({"op": "set", "node": "object-2", "fields": {"texture": ")") +
                                                                  name + R"("}})"),
                                       view),
                        ray::EditError);
}

// `ray view new.json` (issue 50): a new scene saves as the course's JSON, passes the course's
// key rules and loads back; a shape JSON cannot hold is refused at the edit with the reason,
// before anything changes (the file and the document kept as they were).
TEST_CASE("SceneEditor: a new scene named .json saves as the course's JSON", "[viewer][editor][json]") {
    const fs::path folder = fs::temp_directory_path() / ("ray_scene_editor_new_json_" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    const fs::path file = folder / "new.json";
    REQUIRE(ray::opensAsNewScene(file));
    ray::SceneEditor editor(file, ray::newSceneText(file), {});
    const ray::Camera view{{0, 9, 9}, {0, -1, -1}, {0, 1, 0}, 30, 0, 0};
    editor.operate(ray::edit::parseTypedJson(R"({"op": "add-primitive", "shape": "sphere"})"), view);
    CHECK(editor.save() == fs::absolute(file).lexically_normal());
    std::ifstream in(file);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    CHECK(text.rfind("{\n  \"name\": \"root\",\n  \"globalData\": {\n", 0) == 0);
    CHECK(text.find("\"type\": \"sphere\"") != std::string::npos);
    CHECK(ray::test::CourseJsonRules::breaches(text).empty());
    const ray::Scene reloaded = ray::loadScene(file);
    CHECK(reloaded.primitives.size() == 1);
    CHECK(reloaded.lights.size() == 1);

    const std::string before = editor.documentText();
    CHECK_THROWS_WITH(editor.operate(ray::edit::parseTypedJson(R"({"op": "add-primitive", "shape": "torus"})"), view),
                      Catch::Matchers::Contains("torus"));
    CHECK(editor.documentText() == before);
    editor.save();
    std::ifstream again(file);
    CHECK(std::string((std::istreambuf_iterator<char>(again)), {}) == text);
    fs::remove_all(folder);
}

// A course JSON scene opened in the studio saves as .xml (converted: ray convert's mapping),
// templates as masters, lights where their groups place them, the same instances.
TEST_CASE("SceneEditor: a JSON scene saves as .xml", "[viewer][editor][json]") {
    const fs::path folder = fs::temp_directory_path() / ("ray_scene_editor_json_as_xml_" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    const fs::path file = folder / "scene.json";
    std::ofstream(file) << R"({"globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
  "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "heightAngle": 45, "focus": [0, 0, 0]},
  "templateGroups": [{"name": "ball", "primitives": [{"type": "sphere", "diffuse": [1, 0, 0]}]}],
  "groups": [{"translate": [2, 2, 2], "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}]},
             {"translate": [1, 0, 0], "groups": [{"name": "ball"}]}, {"name": "ball"}]}
)";
    ray::SceneEditor editor(file, {});
    const fs::path saved = editor.save("converted.xml");
    std::ifstream in(saved);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    CHECK(text.find("<object type=\"master\" name=\"ball\"/>") != std::string::npos);
    const ray::Scene original = ray::loadScene(file), converted = ray::loadScene(saved);
    REQUIRE(converted.primitives.size() == 2);
    CHECK(converted.lights.size() == 1);
    CHECK(converted.lights[0].position == ray::Vec3{2, 2, 2});
    for (size_t i = 0; i < 2; ++i)
        CHECK(std::memcmp(converted.primitives[i].objectToWorld.m, original.primitives[i].objectToWorld.m,
                          sizeof original.primitives[i].objectToWorld.m) == 0);
    fs::remove_all(folder);
}
