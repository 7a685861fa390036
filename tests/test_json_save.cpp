// Saving a course JSON scene keeps its text (scene/json_splices.h): unedited, a document
// saves to its file's bytes; edited, to the file with the lines of what the edit touched
// changed alone; and what JSON cannot hold is refused with the reason, by the save and by
// the editor before the edit changes anything.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "edit/edit_error.h"
#include "edit/edit_session.h"
#include "ray/ray.h"
#include "scene/json_splices.h"
#include "scene/scene_document.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace ray;
using Catch::Matchers::Contains;

LoadOptions quiet() { return ray::test::quietLoadOptions(false); }

std::string bytesOf(const fs::path& file) { return ray::test::fileText(file); }

std::vector<std::string> linesOf(const std::string& text) { return ray::test::textLines(text); }

// How many lines differ between two texts, as a line diff counts them: the larger of the
// lines it removes and the lines it adds (those off their longest common subsequence).
size_t linesChanged(const std::string& before, const std::string& after) {
    const std::vector<std::string> a = linesOf(before), b = linesOf(after);
    std::vector<std::vector<size_t>> common(a.size() + 1, std::vector<size_t>(b.size() + 1, 0));
    for (size_t i = 1; i <= a.size(); ++i)
        for (size_t j = 1; j <= b.size(); ++j)
            common[i][j] = a[i - 1] == b[j - 1] ? common[i - 1][j - 1] + 1 : std::max(common[i - 1][j], common[i][j - 1]);
    const size_t kept = common[a.size()][b.size()];
    return std::max(a.size() - kept, b.size() - kept);
}

PrimitiveNode* firstPrimitive(SceneDocument& document) {
    PrimitiveNode* found = nullptr;
    forEachObject(document, [&](PrimitiveNode& node, const DocumentPlace&) {
        if (!found) found = &node;
    });
    return found;
}

// The statues' cube of kScene (below): groups[1].primitives[0].
PrimitiveNode* cube(SceneDocument& document) {
    return &std::get<PrimitiveNode>(document.trees.at("root").tree.blocks[1].items[0]);
}

std::string saved(const SceneDocument& document) { return documentToText(document, Resources{}, document.file); }

SceneDocument fromText(const std::string& text, const std::string& name = "scene.json") {
    return loadSceneDocumentFromText(text, fs::temp_directory_path() / "ray_json_save" / name, quiet());
}

// A scene written as people write them: keys in their own order, a focus point, a template.
const char* kScene = R"({
  "name": "root",
  "globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
  "cameraData": {
    "position": [0, 2, 8],
    "up": [0, 1, 0],
    "heightAngle": 45,
    "focus": [0, 0, 0]
  },
  "templateGroups": [
    {
      "name": "post",
      "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}],
      "primitives": [{"type": "cylinder", "diffuse": [0.5, 0.5, 0.5]}]
    }
  ],
  "groups": [
    {
      "translate": [0, 4, 0],
      "lights": [
        {
          "type": "directional",
          "color": [1, 1, 1],
          "direction": [0, -1, 0]
        }
      ]
    },
    {
      "scale": [2, 1, 2],
      "primitives": [
        {
          "type": "cube",
          "diffuse": [1, 0, 0],
          "shininess": 10
        },
        {
          "type": "sphere",
          "diffuse": [0, 1, 0]
        }
      ]
    },
    {
      "translate": [0, 5, 0],
      "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0.1, 0]}]
    },
    {"translate": [-2, 0, 0], "groups": [{"name": "post"}]},
    {"translate": [2, 0, 0], "groups": [{"name": "post"}]}
  ]
}
)";

}  // namespace

TEST_CASE("a JSON scene saves unedited to its own bytes, and a value edited in place", "[json][save]") {
    const SceneDocument document = fromText(kScene);
    CHECK(saved(document) == kScene);

    SceneDocument edited = document;
    cube(edited)->material.diffuse = {0.25, 0, 0};
    const std::string text = saved(edited);
    CHECK(linesChanged(kScene, text) == 1);
    CHECK_THAT(text, Contains(R"("diffuse": [0.25, 0, 0],)"));
    const SceneDocument reread = fromText(text);
    CHECK(cube(const_cast<SceneDocument&>(reread))->material.diffuse == Vec3{0.25, 0, 0});
}

TEST_CASE("a JSON save adds a key on a line of its own, indented like its neighbours", "[json][save]") {
    SceneDocument edited = fromText(kScene);
    cube(edited)->material.specular = {1, 1, 1};
    edited.globals.kt = 0.25;
    const std::string text = saved(edited);
    CHECK_THAT(text, Contains("          \"shininess\": 10,\n          \"specular\": [1, 1, 1]\n        },"));
    CHECK_THAT(text, Contains(R"("specularCoeff": 0.5, "transparentCoeff": 0.25})"));
    CHECK(linesChanged(kScene, text) == 3);  // a line gains a comma, one is added; and the globals' line
    const SceneDocument reread = fromText(text);
    CHECK(reread.globals.kt == 0.25);
}

TEST_CASE("a JSON save removes a primitive or a group with its own lines", "[json][save]") {
    SceneDocument edited = fromText(kScene);
    Block& statues = edited.trees.at("root").tree.blocks[1];
    statues.items.erase(statues.items.begin());  // the cube
    std::string text = saved(edited);
    CHECK_THAT(text, Contains("      \"primitives\": [\n        {\n          \"type\": \"sphere\","));
    CHECK(text.find("cube") == std::string::npos);
    CHECK(fromText(text).primitiveElements == 2);

    SceneDocument lastGone = fromText(kScene);
    lastGone.trees.at("root").tree.blocks[1].items.pop_back();  // the sphere: the cube's comma goes too
    text = saved(lastGone);
    CHECK_THAT(text, Contains("\"shininess\": 10\n        }\n      ]"));
    CHECK(fromText(text).primitiveElements == 2);

    SceneDocument allGone = fromText(kScene);
    allGone.trees.at("root").tree.blocks[1].items.clear();  // an emptied array goes with its key
    text = saved(allGone);
    CHECK_THAT(text, Contains("      \"scale\": [2, 1, 2]\n    },"));
    CHECK(text.find("\"primitives\": [\n") == std::string::npos);
    CHECK(fromText(text).primitiveElements == 1);  // the template's cylinder

    const SceneDocument before = fromText(kScene);
    SceneDocument groupGone = before;
    auto& groups = groupGone.trees.at("root").tree.blocks;
    groups.erase(groups.begin() + 3);  // the first post's placement: its light goes with it
    CHECK(jsonUnsaveable(groupGone, Resources{}));  // the document still has it
    placeLightsByTheirGroups(before, groupGone);     // as the edit session does after an edit
    CHECK(groupGone.lights.size() == 3);
    text = saved(groupGone);
    CHECK(text.find("[-2, 0, 0]") == std::string::npos);
    CHECK_THAT(text, Contains("    },\n    {\"translate\": [2, 0, 0]"));
    CHECK(fromText(text).lights.size() == 3);  // the sun, the lamp, the other post's light
}

TEST_CASE("a JSON save writes transforms, lights and the camera in the file's terms", "[json][save]") {
    SceneDocument edited = fromText(kScene);
    Block& statues = edited.trees.at("root").tree.blocks[1];
    statues.transforms.insert(statues.transforms.begin(), TransformOp{TransformKind::Translate, {0, 1, 0}});
    composeBlock(statues);
    edited.lights[0].direction = {0, -1, -1};  // the sun: in a translated group, the same vector
    edited.camera.position = {0, 3, 8};        // looking the same way: the focus point moves with it
    const std::string text = saved(edited);
    CHECK_THAT(text, Contains("      ],\n      \"translate\": [0, 1, 0]\n    },"));
    CHECK_THAT(text, Contains("\"direction\": [0, -1, -1]"));
    CHECK_THAT(text, Contains("\"position\": [0, 3, 8],"));
    CHECK_THAT(text, Contains("\"focus\": [0, 1, 0]"));
    const SceneDocument reread = fromText(text);
    CHECK(reread.trees.at("root").tree.blocks[1].toParent.m[1][3] == 1);
    CHECK(reread.lights[0].direction == Vec3{0, -1, -1});

    SceneDocument moved = fromText(kScene);
    moved.lights[1].position = {1, 5, 0};  // the lamp's group holds it alone: the group moves
    const std::string movedText = saved(moved);
    CHECK_THAT(movedText, Contains("\"translate\": [1, 5, 0],"));
    CHECK(linesChanged(kScene, movedText) == 1);
    CHECK(fromText(movedText).lights[1].position == Vec3{1, 5, 0});
}

TEST_CASE("what a JSON scene cannot hold is refused with the reason, and the file kept", "[json][save]") {
    const SceneDocument document = fromText(kScene);
    auto refusal = [](const SceneDocument& edited) {
        std::optional<std::string> why = jsonUnsaveable(edited, Resources{});
        REQUIRE(why);
        CHECK_THROWS_WITH(saved(edited), Contains("the scene is not saved, the file is kept as it was"));
        return *why;
    };
    SceneDocument torus = document;
    cube(torus)->type = PrimitiveType::Torus;
    CHECK_THAT(refusal(torus), Contains("groups[1].primitives[0] is now a torus, which a JSON scene has not"));

    SceneDocument emissive = document;
    cube(emissive)->material.emissive = {1, 1, 1};
    CHECK_THAT(refusal(emissive), Contains("has an emissive colour"));

    SceneDocument area = document;
    area.lights[0].type = LightType::Area;
    CHECK_THAT(refusal(area), Contains("groups[0].lights[0] is now a area light, which a JSON scene has not"));

    SceneDocument order = document;
    Block& statues = order.trees.at("root").tree.blocks[1];
    statues.transforms.push_back(TransformOp{TransformKind::Translate, {0, 1, 0}});  // after the scale
    composeBlock(statues);
    CHECK_THAT(refusal(order), Contains("are not in the order translate, rotate, scale, matrix"));

    SceneDocument templateLight = document;
    templateLight.lights[2].color = {0, 0, 1};  // the first post's: one value placed twice
    CHECK_THAT(refusal(templateLight), Contains("templateGroups[0].lights[0] is one light of a template placed 2 times"));

    SceneDocument crowded = fromText(R"({"globalData": {"ambientCoeff": 1, "diffuseCoeff": 1, "specularCoeff": 1},
 "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "heightAngle": 45, "look": [0, 0, -1]},
 "groups": [{"lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}],
             "primitives": [{"type": "sphere"}]}]})");
    crowded.lights[0].position = {0, 1, 0};  // the group would move its sphere too
    CHECK_THAT(refusal(crowded), Contains("a JSON light sits at the origin of its group, groups[0], which holds more "
                                          "than this light"));
}

TEST_CASE("the editor refuses an edit a JSON scene cannot hold before it changes anything", "[json][save][edit]") {
    edit::SessionOptions options;
    options.load = quiet();
    edit::EditSession session(fromText(kScene), options);
    const int id = cube(const_cast<SceneDocument&>(session.document()))->id;
    using edit::FieldOwner, edit::findField;
    const edit::SetFields set{{edit::NodeKind::Object, id}, {{findField(FieldOwner::Object, "emissive"), Vec3{1, 1, 1}}}};
    CHECK_THROWS_WITH(session.apply(set), Contains("the scene is a JSON scene, and the primitive groups[1].primitives[0] "
                                                   "has an emissive colour"));
    CHECK(session.version() == 0);
    CHECK(!session.canUndo());
    CHECK(saved(session.document()) == kScene);

    session.apply(edit::SetFields{set.node, {{findField(FieldOwner::Object, "diffuse"), Vec3{0.5, 0.5, 0.5}}}});
    CHECK(linesChanged(kScene, saved(session.document())) == 1);
    session.undo();
    CHECK(saved(session.document()) == kScene);
}

TEST_CASE("every course JSON scene saves unedited to its own bytes, and a material edit to 3 lines at most",
          "[json][save][corpus]") {
    std::optional<fs::path> shared = ray::test::sharedDir();
    if (!shared || !fs::is_directory(*shared / "cs1230" / "scenefiles")) {
        ray::test::skip("../shared/cs1230 is absent: the course's JSON scenes are not here");
        return;
    }
    std::vector<fs::path> scenes;
    for (const auto& entry : fs::recursive_directory_iterator(*shared / "cs1230" / "scenefiles"))
        if (entry.path().extension() == ".json") scenes.push_back(entry.path());
    std::sort(scenes.begin(), scenes.end());
    REQUIRE(scenes.size() == 105);
    size_t loaded = 0, identical = 0, edited = 0, mostLines = 0;
    for (const fs::path& file : scenes) {
        INFO(file.string());
        SceneDocument document;
        try {
            document = loadSceneDocument(file, quiet());
        } catch (const InputError&) {
            continue;  // the two naming the absent dragon.obj (test_json_scene.cpp)
        }
        ++loaded;
        const std::string bytes = bytesOf(file);
        const std::string text = saved(document);
        CHECK(text == bytes);
        identical += text == bytes;
        if (PrimitiveNode* node = firstPrimitive(document)) {
            node->material.diffuse = {0.12549019607843137, 0.5, 1.0 / 3};  // a picked colour, not 8 bits
            const std::string changed = saved(document);
            const size_t lines = linesChanged(bytes, changed);
            CHECK(lines >= 1);
            CHECK(lines <= 3);
            mostLines = std::max(mostLines, lines);
            const SceneDocument reread = loadSceneDocumentFromText(changed, file, quiet());
            CHECK(firstPrimitive(const_cast<SceneDocument&>(reread))->material.diffuse == node->material.diffuse);
            ++edited;
        }
    }
    std::cout << loaded << " course JSON scenes load; " << identical << " save unedited to their own bytes; " << edited
              << " edited (a diffuse colour) change " << mostLines << " lines at most\n";
    CHECK(loaded == 103);
    CHECK(identical == loaded);
    CHECK(edited == loaded);
}

TEST_CASE("a JSON scene's nodes are named by their places in the file", "[json][save][edit]") {
    edit::SessionOptions options;
    options.load = quiet();
    edit::EditSession session(fromText(kScene), options);
    std::vector<std::string> objects, blocks;
    for (const edit::OutlineEntry& entry : session.outline()) {
        if (entry.id.kind == edit::NodeKind::Object) objects.push_back(session.describe(entry.id).entry.path);
        if (entry.id.kind == edit::NodeKind::Block) blocks.push_back(session.describe(entry.id).entry.path);
    }
    // The trees in the file's order: its templates are written first.
    CHECK(objects == std::vector<std::string>{"templateGroups[0].primitives[0]", "groups[1].primitives[0]",
                                              "groups[1].primitives[1]"});
    CHECK(blocks == std::vector<std::string>{"templateGroups[0]", "groups[0]", "groups[1]", "groups[2]", "groups[3]",
                                             "groups[3].groups[0]", "groups[4]", "groups[4].groups[0]"});
}

// The outline as the page shows it: each entry's label and text, and its place (the tooltip).
std::vector<std::string> outlineLines(edit::EditSession& session) {
    std::vector<std::string> lines;
    for (const edit::OutlineEntry& entry : session.outline()) {
        std::string line = std::string(size_t(entry.depth) * 2, ' ') + entry.label;
        if (!entry.text.empty()) line += " " + entry.text;
        if (!entry.path.empty()) line += " @ " + entry.path;
        CHECK(session.describe(entry.id).entry.path == entry.path);  // /node says the same place
        lines.push_back(line);
    }
    return lines;
}

TEST_CASE("a JSON scene's outline speaks JSON and names its places (lights' too), an XML scene's speaks XML",
          "[json][save][edit][outline]") {
    edit::SessionOptions options;
    options.load = quiet();
    edit::EditSession json(fromText(kScene), options);
    // The trees in the file's order: the template first. Its light, placed twice, is one place.
    const std::vector<std::string> jsonOutline{
        "camera",
        "globals",
        "light directional light @ groups[0].lights[0]",
        "light point light @ groups[2].lights[0]",
        "light point light @ templateGroups[0].lights[0]",
        "light point light @ templateGroups[0].lights[0]",
        "template group post @ templateGroups[0]",
        "  group @ templateGroups[0]",
        "    object cylinder @ templateGroups[0].primitives[0]",
        "groups",
        "  group @ groups[0]",
        "  group @ groups[1]",
        "    object cube @ groups[1].primitives[0]",
        "    object sphere @ groups[1].primitives[1]",
        "  group @ groups[2]",
        "  group @ groups[3]",
        "    group @ groups[3].groups[0]",
        "      template use post @ groups[3].groups[0]",
        "  group @ groups[4]",
        "    group @ groups[4].groups[0]",
        "      template use post @ groups[4].groups[0]"};
    CHECK(outlineLines(json) == jsonOutline);

    // A light's place is its group's as it is now: groups[1] deleted, the point light's group
    // is groups[1]; a light added has no place until the file it is saved to is read again.
    const edit::NodeId statues = json.outline().at(11).id;
    REQUIRE(statues.kind == edit::NodeKind::Block);
    json.apply(edit::DeleteNodes{{statues}});
    std::vector<std::string> lights;
    for (const edit::OutlineEntry& entry : json.outline())
        if (entry.id.kind == edit::NodeKind::Light) lights.push_back(entry.path);
    CHECK(lights == std::vector<std::string>{"groups[0].lights[0]", "groups[1].lights[0]", "templateGroups[0].lights[0]",
                                             "templateGroups[0].lights[0]"});
    edit::AddLight light;
    json.apply(light);
    CHECK(json.outline().at(6).id.kind == edit::NodeKind::Light);
    CHECK(json.outline().at(6).path.empty());

    // The same scene as XML: its kinds' names, "master" before a template's name, XML paths,
    // lights with no place.
    SceneDocument jsonDocument = fromText(kScene);
    edit::EditSession xml(fromText(documentToText(jsonDocument, Resources{}, "scene.xml"), "scene.xml"), options);
    CHECK(outlineLines(xml) == std::vector<std::string>{
                                   "camera",
                                   "globals",
                                   "light directional light",
                                   "light point light",
                                   "light point light",
                                   "light point light",
                                   "tree master post @ post",
                                   "  transblock @ post/transblock[0]",
                                   "    object cylinder @ post/transblock[0]/object[0]",
                                   "tree root @ root",
                                   "  transblock @ root/transblock[0]",
                                   "  transblock @ root/transblock[1]",
                                   "    object cube @ root/transblock[1]/object[0]",
                                   "    object sphere @ root/transblock[1]/object[1]",
                                   "  transblock @ root/transblock[2]",
                                   "  transblock @ root/transblock[3]",
                                   "    transblock @ root/transblock[3]/object[0]/transblock[0]",
                                   "      placement master post @ root/transblock[3]/object[0]/transblock[0]/object[0]",
                                   "  transblock @ root/transblock[4]",
                                   "    transblock @ root/transblock[4]/object[0]/transblock[0]",
                                   "      placement master post @ root/transblock[4]/object[0]/transblock[0]/object[0]"});
    for (const edit::OutlineEntry& entry : xml.outline()) CHECK(entry.label == edit::nodeKindName(entry.id.kind));
}

TEST_CASE("the C++ API edits a JSON scene and saves it as JSON, refusing what JSON cannot hold",
          "[json][save][api]") {
    const fs::path folder = fs::temp_directory_path() / "ray_json_save_api";
    fs::create_directories(folder);
    const fs::path file = folder / "scene.json";
    std::ofstream(file, std::ios::binary) << kScene;
    ray::api::Scene scene = ray::api::Scene::load(file).scene;
    std::vector<std::string> objects;  // the template's cylinder, the cube, the sphere
    std::vector<std::string> labelled;  // the others, as "label text @ path"
    for (const ray::api::OutlineEntry& entry : scene.outline()) {
        if (entry.kind == "object") objects.push_back(entry.node);
        else if (entry.kind != "camera" && entry.kind != "globals" && entry.kind != "light")
            labelled.push_back(entry.label + (entry.text.empty() ? "" : " " + entry.text) + " @ " + entry.path);
    }
    // The outline's words and places reach the API as the studio's (edit/node_views.h).
    CHECK(labelled == std::vector<std::string>{"template group post @ templateGroups[0]", "group @ templateGroups[0]",
                                               "groups @ ", "group @ groups[0]", "group @ groups[1]", "group @ groups[2]",
                                               "group @ groups[3]", "group @ groups[3].groups[0]",
                                               "template use post @ groups[3].groups[0]", "group @ groups[4]",
                                               "group @ groups[4].groups[0]", "template use post @ groups[4].groups[0]"});
    const std::string object = objects.at(1);
    scene.set(object, {{"diffuse", ray::api::Vec3{0, 0, 1}}, {"shininess", 20.0}});
    CHECK_THROWS_WITH(scene.set(object, {{"emissive", ray::api::Vec3{1, 1, 1}}}), Contains("a JSON scene"));
    scene.save(file);
    const std::string text = bytesOf(file);
    CHECK(linesChanged(kScene, text) == 2);
    CHECK_THAT(text, Contains(R"("diffuse": [0, 0, 1],)"));
    CHECK_THAT(text, Contains(R"("shininess": 20)"));
    scene.save(folder / "scene.xml");  // under an XML name: written as XML (json_writer.h's other way)
    CHECK_THAT(bytesOf(folder / "scene.xml"), Contains("<scenefile>"));
    CHECK(ray::api::Scene::load(folder / "scene.xml").scene.outline().size() == scene.outline().size());
    fs::remove_all(folder);
}

TEST_CASE("a JSON scene's lights follow their groups", "[json][save][edit]") {
    edit::SessionOptions options;
    options.load = quiet();
    edit::EditSession session(fromText(kScene), options);
    using edit::FieldOwner, edit::findField;
    const SceneDocument& document = session.document();
    const int lampGroup = document.trees.at("root").tree.blocks[2].id;
    session.apply(edit::SetFields{{edit::NodeKind::Block, lampGroup},
                                  {{findField(FieldOwner::Block, "transform"),
                                    std::vector<TransformOp>{TransformOp{TransformKind::Translate, {1, 5, 0}}}}}});
    CHECK(session.document().lights[1].position == Vec3{1, 5, 0});
    const std::string text = saved(session.document());
    CHECK(linesChanged(kScene, text) == 1);
    CHECK_THAT(text, Contains("\"translate\": [1, 5, 0],"));

    const int secondPost = document.trees.at("root").tree.blocks[4].id;  // its placement's group: the post's light goes
    session.apply(edit::DeleteNodes{{{edit::NodeKind::Block, secondPost}}});
    CHECK(session.document().lights.size() == 3);
    CHECK(fromText(saved(session.document())).lights.size() == 3);
    session.undo();
    CHECK(session.document().lights.size() == 4);
}
