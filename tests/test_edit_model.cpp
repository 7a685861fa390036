// The one edit model (host/edit/, docs/modeler-protocol.md): its field table, its
// operations checked whole and saying what they changed, its history by user action, and
// what the editor shows being what the saved file loads to.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <unistd.h>

#include "edit/edit_error.h"
#include "edit/edit_json.h"
#include "edit/edit_session.h"
#include "edit/field_table.h"
#include "edit/struct_fields.h"
#include "scene/document_fields.h"
#include "scene/scene_difference.h"
#include "scene/scene_loader.h"
#include "scene/xml_characters.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace ray;
using namespace ray::edit;
using nlohmann::json;

LoadOptions quiet() { return ray::test::quietLoadOptions(); }

// A folder of its own with a copy of `scene` (from scenes/), its textures, a texture and a
// mesh beside it: what an edit may name.
fs::path scratchCopy(const std::string& scene, const std::string& name) {
    const fs::path folder = fs::temp_directory_path() / ("ray_edit_model_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    fs::copy(test::scenesDir() / "textures", folder / "textures", fs::copy_options::recursive);
    fs::copy_file(test::scenesDir() / "textures" / "wood.png", folder / "wood.png");
    fs::copy_file(test::scenesDir() / "meshes" / "vase.obj", folder / "vase.obj");
    fs::copy_file(test::scenesDir() / scene, folder / scene);
    return folder / scene;
}

EditSession sessionOf(const fs::path& file) { return EditSession(loadSceneDocument(file, quiet()), {quiet(), true, {}}); }

std::string textOf(const EditSession& session) {
    return documentToText(session.document(), session.resources(), session.document().file);
}

// An operation as the page sends it.
Operation op(const std::string& request) { return operationFromJson(parseTypedJson(request)).operation; }

SceneChanges rendered(SceneChanges changes) {
    changes.camera = false;  // each frame's camera is its own
    return changes;
}

// Applies `request` and checks that what it said it changed covers what changed.
Outcome applyChecked(EditSession& session, const std::string& request, const std::string& action = {}) {
    INFO(request);
    const std::shared_ptr<const Scene> before = session.scene();
    const Outcome outcome = session.apply(op(request), action);
    const SceneChanges found = rendered(compareScenes(*before, *session.scene()));
    CHECK(outcome.changes.covers(found));
    if (outcome.changes.geometry && outcome.changes.transformsOnly)
        CHECK(before->primitives.size() == session.scene()->primitives.size());
    return outcome;
}

// What the editor shows is what its saved text loads to.
void checkSavesAsShown(const EditSession& session) {
    const std::string text = textOf(session);
    SceneDocument document = loadSceneDocumentFromText(text, session.document().file, quiet());
    Resources resources;
    const Scene loaded = flattenDocument(document, resources, quiet());
    INFO(text);
    const SceneChanges difference = compareRendered(loaded, *session.scene());
    std::string parts;
    for (const std::string& part : difference.names()) parts += part + " ";
    INFO("differing: " << parts);
    CHECK_FALSE(difference.any());
    const Camera& shown = session.scene()->camera;
    CHECK(loaded.camera.position == shown.position);
    CHECK(length(cross(normalize(loaded.camera.look), normalize(shown.look))) < 1e-12);
}

std::string firstOf(EditSession& session, const std::string& kind, int skip = 0) {
    for (const OutlineEntry& entry : session.outline())
        if (nodeKindName(entry.id.kind) == kind && skip-- == 0) return entry.id.text();
    FAIL("no " << kind);
    return {};
}

}  // namespace

TEST_CASE("The field table holds every field the saver writes, once, with its rule and help", "[edit]") {
    std::set<std::pair<int, std::string>> names;
    for (const EditField& field : editFields()) {
        INFO(field.name);
        CHECK(names.insert({int(field.owner), std::string(field.name)}).second);  // no field twice
        CHECK_FALSE(field.help.empty());
        const bool numbers = field.kind == FieldKind::Number || field.kind == FieldKind::Color ||
                             field.kind == FieldKind::Vector;
        CHECK(numbers == (field.rule != nullptr));
        CHECK(findField(field.owner, field.keyword()) == &field);
    }
    auto has = [&](FieldOwner owner, const char* name) { return names.count({int(owner), name}) == 1; };
    for (const auto& f : kMaterialTriples) CHECK(has(FieldOwner::Object, f.element));
    for (const auto& f : kMaterialSingles) CHECK(has(FieldOwner::Object, f.element));
    for (const auto& f : kLightTriples) CHECK(has(FieldOwner::Light, f.element));
    for (const auto& f : kLightSingles) CHECK(has(FieldOwner::Light, f.element));
    for (const auto& f : kCameraTriples) CHECK(has(FieldOwner::Camera, f.element));
    for (const auto& f : kCameraSingles) CHECK(has(FieldOwner::Camera, f.element));
    for (const auto& f : kGlobalsSingles) CHECK(has(FieldOwner::Globals, f.element));
    const json table = fieldTableJson();
    CHECK(table["fields"].size() == editFields().size());
    CHECK(table["fields"][0]["name"] == "diffuse");
    CHECK(table["fields"][0]["min"] == 0);
}

TEST_CASE("Every operation says what it changed, covering what a comparison of the scenes finds, and saves as shown",
          "[edit]") {
    EditSession session = sessionOf(scratchCopy("depth_of_field.xml", "ops"));
    const Outcome added = applyChecked(session, R"({"op": "add-primitive", "shape": "sphere",
        "fields": {"diffuse": [0.25, 0.5, 1], "shininess": 12, "transform": [{"kind": "translate", "v": [0, 1, 0]}]}})");
    REQUIRE(added.added.size() == 2);
    const std::string sphere = added.added[0].text();
    CHECK(added.changes.geometry);
    CHECK_FALSE(added.changes.transformsOnly);
    CHECK(added.outline);

    // A material edit: the materials alone; a move: a refit; a light, the globals: those alone.
    Outcome o = applyChecked(session, R"({"op": "set", "node": ")" + sphere + R"(", "fields": {"diffuse": [1, 0, 0]}})");
    CHECK(o.changes.names() == std::vector<std::string>{"materials"});
    o = applyChecked(session, R"({"op": "set", "node": ")" + sphere + R"(", "fields": {"world": [1,0,0,2, 0,1,0,1, 0,0,1,0]}})");
    CHECK(o.changes.names() == std::vector<std::string>{"transforms"});
    o = applyChecked(session, R"({"op": "set", "node": ")" + firstOf(session, "light") + R"(", "fields": {"color": [0.5, 0.5, 0.5]}})");
    CHECK(o.changes.names() == std::vector<std::string>{"lights"});
    o = applyChecked(session, R"({"op": "set", "node": "globals", "fields": {"ambientcoeff": 0.25}})");
    CHECK(o.changes.names() == std::vector<std::string>{"globals"});
    o = applyChecked(session, R"({"op": "set", "node": ")" + sphere + R"(", "fields": {"texture": "wood.png", "texture.u": 3}})");
    CHECK(o.changes.materials);
    CHECK(o.changes.images);

    // The other operations, each once; the shapes and lights of every kind.
    for (const char* shape : {"cube", "cylinder", "cone", "torus"})
        applyChecked(session, std::string(R"({"op": "add-primitive", "shape": ")") + shape + R"("})");
    applyChecked(session, R"({"op": "add-primitive", "shape": "mesh", "file": "vase.obj"})");
    for (const char* type : {"point", "directional", "spot", "area"})
        applyChecked(session, std::string(R"({"op": "add-light", "type": ")") + type + R"("})");
    const Outcome copy = applyChecked(session, R"({"op": "duplicate", "nodes": [")" + sphere + R"("]})");
    applyChecked(session, R"({"op": "group", "nodes": [")" + sphere + R"(", ")" + copy.added[0].text() + R"("]})");
    applyChecked(session, R"({"op": "rename", "node": "tree-0", "name": "marble"})");
    const std::string placement = firstOf(session, "placement");
    const Outcome unique = applyChecked(session, R"({"op": "make-unique", "node": ")" + placement + R"("})");
    CHECK(unique.added.front().kind == NodeKind::Tree);
    applyChecked(session, R"({"op": "set", "node": "camera", "fields": {"pos": [0, 2, 8], "look": [0, -0.25, -1]}})");
    applyChecked(session, R"({"op": "delete", "nodes": ["object-1", ")" + firstOf(session, "light") + R"("]})");
    checkSavesAsShown(session);
}

TEST_CASE("make-unique: editing the copy changes that placement alone, editing a master changes every placement",
          "[edit]") {
    EditSession session = sessionOf(scratchCopy("depth_of_field.xml", "unique"));
    auto diffuseCount = [&](const Vec3& color) {
        size_t n = 0;
        for (const PrimitiveInstance& p : session.scene()->primitives)
            n += session.scene()->materials[size_t(p.material)].diffuse == color ? 1 : 0;
        return n;
    };
    session.apply(op(R"({"op": "set", "node": "object-0", "fields": {"diffuse": [0, 1, 0]}})"));
    CHECK(diffuseCount({0, 1, 0}) == 5);  // the ball master placed five times
    session.apply(op(R"({"op": "make-unique", "node": ")" + firstOf(session, "placement") + R"("})"));
    const std::string copied = firstOf(session, "object", 2);  // after the ball's and the floor's: the copy's
    session.apply(op(R"({"op": "set", "node": ")" + copied + R"(", "fields": {"diffuse": [0, 0, 1]}})"));
    CHECK(diffuseCount({0, 0, 1}) == 1);
    CHECK(diffuseCount({0, 1, 0}) == 4);
    checkSavesAsShown(session);
}

TEST_CASE("Bad edits are refused with a sentence naming the field, and change nothing", "[edit]") {
    EditSession session = sessionOf(scratchCopy("shadows.xml", "bad"));
    const std::string text = textOf(session);
    const std::shared_ptr<const Scene> scene = session.scene();
    const uint64_t version = session.version();
    auto refusedJson = [&](const std::string& request, const std::string& words, const std::string& field) {
        INFO(request);
        try {
            session.apply(op(request));
            FAIL("accepted");
        } catch (const EditError& e) {
            CHECK_THAT(e.what(), Catch::Matchers::Contains(words));
            CHECK(e.field == field);
            CHECK(std::string(e.what()).size() < 400);
        }
        CHECK(session.scene() == scene);
        CHECK(session.version() == version);
        CHECK_FALSE(session.canUndo());
        CHECK(textOf(session) == text);
    };
    auto refused = [&](const Operation& operation, const std::string& words, const std::string& field) {
        INFO(words);
        try {
            session.apply(operation);
            FAIL("accepted");
        } catch (const EditError& e) {
            CHECK_THAT(e.what(), Catch::Matchers::Contains(words));
            CHECK(e.field == field);
        }
        CHECK(session.scene() == scene);
        CHECK(session.version() == version);
        CHECK_FALSE(session.canUndo());
        CHECK(textOf(session) == text);
    };
    const EditField* shininess = findField(FieldOwner::Object, "shininess");
    const EditField* transform = findField(FieldOwner::Object, "transform");
    const EditField* name = findField(FieldOwner::Tree, "name");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    refused(SetFields{{NodeKind::Object, 0}, {{shininess, -1.0}}}, "shininess must be 0 or more, not -1", "shininess");
    TransformOp flat;
    flat.kind = TransformKind::Scale;
    flat.v = {1, 0, 1};
    refused(SetFields{{NodeKind::Object, 0}, {{transform, std::vector<TransformOp>{flat}}}}, "zero scale", "transform");
    refused(SetFields{{NodeKind::Object, 0}, {{shininess, nan}}}, "shininess", "shininess");
    refused(SetFields{{NodeKind::Object, 0}, {{findField(FieldOwner::Object, "diffuse"), Vec3{1, nan, 0}}}}, "diffuse",
            "diffuse");
    refused(SetFields{{NodeKind::Object, 999}, {{shininess, 1.0}}}, "object-999 does not exist", "");
    refused(SetFields{{NodeKind::Tree, 0}, {{name, std::string(100000, 'n')}}}, "100000 characters long", "name");
    refusedJson(R"({"op": "set", "node": "object-0", "fields": {"shininess": "shiny"}})", "shininess takes a number",
                "shininess");
    refusedJson(R"({"op": "set", "node": "object-0", "fields": {"diffuse": [1, 0]}})", "diffuse takes a color",
                "diffuse");
    refusedJson(R"({"op": "set", "node": "object-0", "fields": {"texture": "../shadows.png"}})", "texture", "texture");
    refusedJson(R"({"op": "set", "node": "object-0", "fields": {"texture": "missing.png"}})", "texture", "texture");
    refusedJson(R"({"op": "set", "node": "camera", "fields": {"look": [0, 1, 0], "up": [0, 2, 0]}})", "up", "up");
    refusedJson(R"({"op": "delete", "nodes": ["object-0", "object-999"]})", "object-999 does not exist", "");
    refusedJson(R"({"op": "rename", "node": "tree-0", "name": "other"})", "the tree named root is the scene", "name");
    CHECK_THROWS_WITH(op(R"({"op": "set", "node": "object-0", "fields": {"glow": 1}})"), Catch::Matchers::Contains("no field 'glow'"));
    CHECK_THROWS_WITH(parseTypedJson("{\"op\": "), Catch::Matchers::Contains("not JSON"));
}

TEST_CASE("Names and files an edit writes are what XML can hold, counted and cut in characters", "[edit]") {
    const fs::path folder = scratchCopy("shadows.xml", "writable").parent_path();
    std::string master = "a";
    for (int i = 0; i < 200; ++i) master += "\xC3\xA9";  // a name of 201 characters, 401 bytes, in the file
    const fs::path file = folder / "masters.xml";
    std::ofstream(file) << "<scenefile>\n  <object type=\"tree\" name=\"" << master << "\">\n"
                        << "    <transblock><object type=\"primitive\" name=\"sphere\"/></transblock>\n  </object>\n"
                        << "  <object type=\"tree\" name=\"root\">\n"
                        << "    <transblock><object type=\"master\" name=\"" << master << "\"/></transblock>\n"
                        << "    <transblock><translate x=\"2\" y=\"0\" z=\"0\"/><object type=\"master\" name=\""
                        << master << "\"/></transblock>\n  </object>\n</scenefile>\n";
    EditSession session = sessionOf(file);
    const std::string tree = firstOf(session, "tree");  // the master, first in the file

    SECTION("make-unique cuts a long name between characters, and the save reloads") {
        session.apply(op(R"({"op": "make-unique", "node": ")" + firstOf(session, "placement") + R"("})"));
        std::string made;
        for (const auto& [name, named] : session.document().trees)
            if (name != master && name != "root") made = name;
        INFO(made);
        CHECK_FALSE(firstUnwritableCharacter(made));
        CHECK(characterCount(made) == kMaxTreeName);
        CHECK(made.ends_with("\xC3\xA9_2"));
        CHECK(made.starts_with("a\xC3\xA9"));
        CHECK_NOTHROW(outlineJson(session.outline()).dump());  // the viewer's /outline
        saveDocument(session.document(), session.resources(), file);
        SceneDocument reloaded = loadSceneDocument(file, quiet());
        CHECK(reloaded.trees.count(made) == 1);
        checkSavesAsShown(session);
    }
    SECTION("a name's length is counted in characters") {
        std::string hundred;
        for (int i = 0; i < 100; ++i) hundred += "\xC3\xA9";
        session.apply(op(R"({"op": "rename", "node": ")" + tree + R"(", "name": ")" + hundred + R"("})"));
        CHECK(session.document().trees.count(hundred) == 1);
        checkSavesAsShown(session);
        const std::string tooLong = hundred + hundred;
        CHECK_THROWS_WITH(session.apply(op(R"({"op": "rename", "node": ")" + tree + R"(", "name": ")" + tooLong + R"("})")),
                          Catch::Matchers::Contains("name is 200 characters long; at most 128 are allowed"));
    }
    SECTION("U+FFFE, U+FFFF and bytes not UTF-8 are refused at the edit, naming the field and the character") {
        const std::string text = textOf(session);
        const uint64_t version = session.version();
        auto refused = [&](const Operation& operation, const std::string& sentence, const std::string& field) {
            INFO(sentence);
            try {
                session.apply(operation);
                FAIL("accepted");
            } catch (const EditError& e) {
                CHECK(std::string(e.what()) == sentence);
                CHECK(e.field == field);
            }
            CHECK(session.version() == version);
            CHECK(textOf(session) == text);
        };
        refused(op(R"({"op": "rename", "node": ")" + tree + R"(", "name": "ab\uFFFF"})"),
                "name: U+FFFF at character 3 cannot be written in an XML file", "name");
        refused(op(R"({"op": "set", "node": "object-0", "fields": {"texture": "wood\uFFFE.png"}})"),
                "texture: U+FFFE at character 5 cannot be written in an XML file", "texture");
        refused(op(R"({"op": "set", "node": "object-0", "fields": {"bumpmap": "\uFFFFwood.png"}})"),
                "bumpmap: U+FFFF at character 1 cannot be written in an XML file", "bumpmap");
        refused(op(R"({"op": "add-primitive", "shape": "mesh", "file": "v\uFFFF.obj"})"),
                "file: U+FFFF at character 2 cannot be written in an XML file", "file");
        const EditField* name = findField(FieldOwner::Tree, "name");
        refused(SetFields{NodeId::parse(tree).value(), {{name, std::string("ab\xC3")}}},
                "name: byte 0xC3 (not UTF-8) at character 3 cannot be written in an XML file", "name");
        refused(SetFields{NodeId::parse(tree).value(), {{name, std::string("x\xED\xA0\x80")}}},
                "name: byte 0xED (not UTF-8) at character 2 cannot be written in an XML file", "name");
    }
}

TEST_CASE("One user action is one undo step: a drag's requests share an action id, undo and redo are unlimited",
          "[edit]") {
    EditSession session = sessionOf(scratchCopy("shadows.xml", "history"));
    const std::string original = textOf(session);
    for (double x : {0.5, 1.0, 1.5})  // a drag: three moves, one action
        session.apply(op(R"({"op": "set", "node": "object-1", "fields": {"world": [1,0,0,)" + std::to_string(x) +
                         R"(, 0,1,0,0.5, 0,0,1,0]}})"),
                      "drag-1");
    session.apply(op(R"({"op": "set", "node": "object-1", "fields": {"shininess": 5}})"));  // a committed field
    session.apply(op(R"({"op": "set", "node": "object-1", "fields": {"shininess": 7}})"));  // another: a step of its own
    CHECK(session.undoSteps() == 3);
    const std::string edited = textOf(session);
    for (int i = 0; i < 3; ++i) REQUIRE(session.undo());
    CHECK_FALSE(session.undo());
    CHECK(textOf(session) == original);
    CHECK_FALSE(session.modified());
    for (int i = 0; i < 3; ++i) REQUIRE(session.redo());
    CHECK(textOf(session) == edited);
    // A cancelled drag: reverted and forgotten.
    session.apply(op(R"({"op": "set", "node": "object-1", "fields": {"world": [1,0,0,9, 0,1,0,0, 0,0,1,0]}})"), "drag-2");
    CHECK(session.revert("drag-2"));
    CHECK_FALSE(session.canRedo());
    CHECK(textOf(session) == edited);
    CHECK_FALSE(session.revert("drag-1"));  // not the latest step
}

TEST_CASE("A number is saved as it was typed, a drag's move keeps the file's translate", "[edit]") {
    EditSession session = sessionOf(scratchCopy("shadows.xml", "typed"));
    session.apply(op(R"({"op": "set", "node": "object-0", "fields": {"shininess": 12.50, "diffuse": [0.30, 1e-1, 1]}})"));
    const std::string text = textOf(session);
    CHECK_THAT(text, Catch::Matchers::Contains("<shininess v=\"12.50\"/>"));
    CHECK_THAT(text, Catch::Matchers::Contains("r=\"0.30\" g=\"1e-1\" b=\"1\""));
    // A move by the gizmo: the object's own translate takes it, no <matrix> appears.
    const FieldValue world = session.describe({NodeKind::Object, 1}).fields.back().second;
    Affine moved = std::get<Affine>(world);
    moved.m[0][3] += 0.25;
    session.apply(SetFields{{NodeKind::Object, 1}, {{findField(FieldOwner::Object, "world"), moved}}});
    CHECK(textOf(session).find("<matrix>") == std::string::npos);
    checkSavesAsShown(session);
}

TEST_CASE("Every course scene that loads takes a material edit through the edit model and saves as shown",
          "[edit][corpus]") {
    const auto shared = test::sharedDir();
    if (!shared) return test::skip("no course data");
    size_t edited = 0;
    for (const fs::path& file : test::courseScenes(*shared)) {
        std::optional<EditSession> session;
        try {
            LoadOptions options = quiet();
            options.loadImages = false;
            session.emplace(loadSceneDocument(file, options), SessionOptions{options, true, {}});
        } catch (const InputError&) {
            continue;  // the corpus's broken files
        }
        INFO(file.filename().string());
        const std::vector<OutlineEntry> nodes = session->outline();
        auto object = std::find_if(nodes.begin(), nodes.end(), [](const OutlineEntry& e) { return e.id.kind == NodeKind::Object; });
        if (object == nodes.end()) continue;
        const std::shared_ptr<const Scene> before = session->scene();
        const Outcome outcome = session->apply(SetFields{object->id, {{findField(FieldOwner::Object, "shininess"), 7.0}}});
        CHECK(outcome.changes.covers(rendered(compareScenes(*before, *session->scene()))));
        CHECK(outcome.changes.names() == std::vector<std::string>{"materials"});
        ++edited;
    }
    CHECK(edited > 200);
}
