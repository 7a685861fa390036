// Issue 49's versions and bounded undo (host/edit/): history kept as what each step changed
// (edit/document_patch.h), counted and capped, undo and redo giving back the very documents;
// ids kept across a reload (edit/node_matching.h); a save that does not replace a file
// changed on disk since it was read (edit/file_stamp.h), in the viewer's editor and the
// C++ API; an edit made against another revision refused.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <set>
#include <sstream>
#include <string>

#include <unistd.h>

#include "edit/edit_json.h"
#include "edit/edit_session.h"
#include "edit/node_places.h"
#include "ray/scene.h"
#include "scene/scene_loader.h"
#include "test_support.h"
#include "viewer/scene_editor.h"

namespace {

namespace fs = std::filesystem;
using namespace ray;
using namespace ray::edit;

LoadOptions quiet() { return ray::test::quietLoadOptions(); }

fs::path scratchFolder(const std::string& name) {
    const fs::path folder = fs::temp_directory_path() / ("ray_edit_history_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    return folder;
}

void writeFile(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::binary);
    out << text;
}

std::string readFile(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// A transblock holding one sphere at x = `x`, of grey `grey`.
std::string sphereBlock(int x, double grey = 0.5) {
    const std::string g = std::to_string(grey);
    return "    <transblock>\n      <translate x=\"" + std::to_string(x) + "\" y=\"0\" z=\"0\"/>\n"
           "      <object type=\"primitive\" name=\"sphere\">\n        <diffuse r=\"" + g + "\" g=\"" + g + "\" b=\"" +
           g + "\"/>\n      </object>\n    </transblock>\n";
}

std::string sceneOf(const std::string& blocks, const std::string& extra = "") {
    return "<scenefile>\n  <cameradata>\n    <pos x=\"0\" y=\"0\" z=\"10\"/>\n    <focus x=\"0\" y=\"0\" z=\"0\"/>\n"
           "    <up x=\"0\" y=\"1\" z=\"0\"/>\n    <heightangle v=\"45\"/>\n  </cameradata>\n"
           "  <lightdata>\n    <id v=\"0\"/>\n    <type v=\"point\"/>\n    <color r=\"1\" g=\"1\" b=\"1\"/>\n"
           "    <position x=\"3\" y=\"3\" z=\"3\"/>\n  </lightdata>\n" + extra +
           "  <object type=\"tree\" name=\"root\">\n" + blocks + "  </object>\n</scenefile>\n";
}

std::string spheres(int count) {
    std::string blocks;
    for (int i = 0; i < count; ++i) blocks += sphereBlock(i);
    return blocks;
}

std::string textOf(const EditSession& session) {
    return documentToText(session.document(), session.resources(), session.document().file);
}

Operation op(const std::string& request) { return operationFromJson(parseTypedJson(request)).operation; }

Operation colourOf(int object, double r) {
    return op(R"({"op": "set", "node": "object-)" + std::to_string(object) + R"(", "fields": {"diffuse": [)" +
              std::to_string(r) + R"(, 0.25, 0.75]}})");
}

// The process's resident memory, in bytes (Linux).
size_t residentBytes() {
    std::ifstream statm("/proc/self/statm");
    size_t pages = 0, resident = 0;
    statm >> pages >> resident;
    return resident * size_t(::sysconf(_SC_PAGESIZE));
}

// The objects' ids in document order, with the translate x of each one's transblock.
std::map<int, int> objectsByPlace(EditSession& session) {
    std::map<int, int> ids;  // x -> id
    SceneDocument document = session.document();
    walkNodes(document, [&](const NodePlace& place) {
        if (place.id.kind == NodeKind::Object) ids[int(place.blocks.front()->transforms.at(0).v[0])] = place.id.number;
        return false;
    });
    return ids;
}

}  // namespace

TEST_CASE("Undo history of 20,000 spheres and 200 colour edits stays small, and undo and redo give back each "
          "document exactly",
          "[edit-history]") {
    const fs::path file = scratchFolder("memory") / "spheres.xml";
    writeFile(file, sceneOf(spheres(20000)));
    EditSession session(loadSceneDocument(file, quiet()), {quiet(), true, {}});
    const size_t rssBefore = residentBytes();
    std::vector<size_t> hashes;  // of each document before each edit, and after the last
    std::map<int, std::string> texts;  // a few of them whole
    for (int edit = 0; edit < 200; ++edit) {
        const std::string text = textOf(session);
        hashes.push_back(std::hash<std::string>{}(text));
        if (edit % 50 == 0) texts[edit] = text;
        session.apply(colourOf((edit * 97) % 20000, 0.001 * (edit + 1)), "pick-" + std::to_string(edit));
    }
    const std::string last = textOf(session);
    hashes.push_back(std::hash<std::string>{}(last));
    const size_t rssGrowth = residentBytes() - std::min(residentBytes(), rssBefore);
    // The figures issue 49 asks for (under 100 MB), printed for the record.
    std::cout << "20,000 spheres, 200 colour edits: history " << session.historyBytes() << " bytes, RSS growth "
              << rssGrowth << " bytes\n";
    CHECK(session.undoSteps() == 200);
    CHECK(session.historyBytes() > 0);
    CHECK(session.historyBytes() < size_t(100) << 20);
    CHECK(session.historyBytes() < size_t(2) << 20);  // a sphere's transblock a step, not the scene
    CHECK(rssGrowth < size_t(100) << 20);
    CHECK(session.droppedSteps() == 0);

    for (int edit = 199; edit >= 0; --edit) {
        REQUIRE(session.undo());
        const std::string text = textOf(session);
        CHECK(std::hash<std::string>{}(text) == hashes[size_t(edit)]);
        if (texts.count(edit)) CHECK(text == texts[edit]);
    }
    CHECK_FALSE(session.canUndo());
    CHECK_FALSE(session.modified());
    for (int edit = 0; edit < 200; ++edit) REQUIRE(session.redo());
    CHECK(textOf(session) == last);
    CHECK(session.historyBytes() < size_t(2) << 20);
}

TEST_CASE("A colour picked in many moves is one step, and the history's limit drops the oldest steps first",
          "[edit-history]") {
    const fs::path file = scratchFolder("limit") / "spheres.xml";
    writeFile(file, sceneOf(spheres(50)));
    SECTION("one gesture, one step") {
        EditSession session(loadSceneDocument(file, quiet()), {quiet(), true, {}});
        const std::string before = textOf(session);
        for (int move = 1; move <= 40; ++move) session.apply(colourOf(3, 0.02 * move), "pick-diffuse-1");
        const std::string after = textOf(session);
        CHECK(session.undoSteps() == 1);
        REQUIRE(session.undo());
        CHECK(textOf(session) == before);
        REQUIRE(session.redo());
        CHECK(textOf(session) == after);
    }
    SECTION("the cap") {
        SessionOptions options{quiet(), true, {}};
        options.historyLimit = 16 * 1024;
        EditSession session(loadSceneDocument(file, quiet()), options);
        std::vector<std::string> texts;
        for (int edit = 0; edit < 60; ++edit) {
            texts.push_back(textOf(session));
            session.apply(colourOf(edit % 50, 0.01 * (edit + 1)));
            CHECK(session.historyBytes() <= options.historyLimit);
        }
        const size_t kept = session.undoSteps();
        INFO(kept << " steps kept, " << session.droppedSteps() << " dropped");
        CHECK(kept > 0);
        CHECK(kept < 60);
        CHECK(session.droppedSteps() == 60 - kept);
        // The steps kept are the latest: undoing them all gives the document before the
        // first of them, not the file's.
        while (session.undo()) {}
        CHECK(textOf(session) == texts[60 - kept]);
    }
}

TEST_CASE("Undo and redo of every kind of operation give back the very documents, masters and csg included",
          "[edit-history]") {
    for (const char* scene : {"csg_nested.xml", "showpiece.xml", "primitives_all.xml"}) {
        const fs::path file = test::scenesDir() / scene;
        if (!fs::exists(file)) continue;
        EditSession session(loadSceneDocument(file, quiet()), {quiet(), true, {}});
        std::vector<std::string> texts{textOf(session)};
        std::vector<NodeId> objects, blocks, placements, trees, lights;
        for (const OutlineEntry& entry : session.outline()) {
            if (entry.id.kind == NodeKind::Object) objects.push_back(entry.id);
            if (entry.id.kind == NodeKind::Block) blocks.push_back(entry.id);
            if (entry.id.kind == NodeKind::Placement) placements.push_back(entry.id);
            if (entry.id.kind == NodeKind::Tree) trees.push_back(entry.id);
            if (entry.id.kind == NodeKind::Light) lights.push_back(entry.id);
        }
        INFO(scene);
        auto tryApply = [&](const std::string& request) {
            try {
                session.apply(op(request));
                texts.push_back(textOf(session));
            } catch (const EditError&) {
            }
        };
        tryApply(R"({"op": "add-primitive", "shape": "cube"})");
        if (!objects.empty()) {
            tryApply(R"({"op": "set", "node": ")" + objects.back().text() + R"(", "fields": {"shininess": 3}})");
            tryApply(R"({"op": "set", "node": ")" + objects.front().text() +
                     R"(", "fields": {"world": [1,0,0,1, 0,1,0,2, 0,0,1,3]}})");
            tryApply(R"({"op": "duplicate", "nodes": [")" + objects.front().text() + R"("]})");
            tryApply(R"({"op": "delete", "nodes": [")" + objects.back().text() + R"("]})");
        }
        if (blocks.size() > 1) tryApply(R"({"op": "delete", "nodes": [")" + blocks[1].text() + R"("]})");
        if (!placements.empty())
            tryApply(R"({"op": "make-unique", "placement": ")" + placements.front().text() + R"("})");
        if (trees.size() > 1) tryApply(R"({"op": "set", "node": ")" + trees[1].text() + R"(", "fields": {"name": "renamed"}})");
        if (!lights.empty()) tryApply(R"({"op": "set", "node": ")" + lights.front().text() + R"(", "fields": {"color": [0.2, 0.3, 0.4]}})");
        tryApply(R"({"op": "add-light", "type": "spot"})");
        REQUIRE(texts.size() >= 4);
        REQUIRE(session.undoSteps() == texts.size() - 1);
        for (size_t i = texts.size() - 1; i-- > 0;) {
            REQUIRE(session.undo());
            CHECK(textOf(session) == texts[i]);
        }
        for (size_t i = 1; i < texts.size(); ++i) {
            REQUIRE(session.redo());
            CHECK(textOf(session) == texts[i]);
        }
    }
}

TEST_CASE("A reload keeps the ids of the elements that are the same, and new ones get ids never used", "[edit-history]") {
    const fs::path file = scratchFolder("reload") / "scene.xml";
    std::string blocks;
    for (int i = 0; i < 6; ++i) blocks += sphereBlock(i * 10);
    writeFile(file, sceneOf(blocks));
    EditSession session(loadSceneDocument(file, quiet()), {quiet(), true, {}});
    const std::map<int, int> before = objectsByPlace(session);  // x -> id
    REQUIRE(before.size() == 6);
    const int lightBefore = session.document().lightIds.at(0);

    // Another program adds a sphere above the others, recolours the third, removes the fifth.
    std::string changed = sphereBlock(-10);
    for (int i = 0; i < 6; ++i)
        if (i != 4) changed += sphereBlock(i * 10, i == 2 ? 0.9 : 0.5);
    writeFile(file, sceneOf(changed));
    session.reload(loadSceneDocument(file, quiet()), {});
    const std::map<int, int> after = objectsByPlace(session);
    REQUIRE(after.size() == 6);
    for (int x : {0, 10, 20, 30, 50}) CHECK(after.at(x) == before.at(x));  // the recoloured one too
    std::set<int> oldIds;
    for (const auto& [x, id] : before) oldIds.insert(id);
    CHECK_FALSE(oldIds.count(after.at(-10)));  // new: an id of its own
    CHECK(session.document().lightIds.at(0) == lightBefore);
    // The removed one's id names nothing: a stale delete deletes nothing else.
    const NodeId removed{NodeKind::Object, before.at(40)};
    CHECK_THROWS_AS(session.apply(DeleteNodes{{removed}}), EditError);
    CHECK(objectsByPlace(session).size() == 6);
    // Blocks keep theirs as well: the unchanged file read again keeps every id.
    const std::vector<OutlineEntry> outline = session.outline();
    session.reload(loadSceneDocument(file, quiet()), {});
    const std::vector<OutlineEntry> again = session.outline();
    REQUIRE(again.size() == outline.size());
    for (size_t i = 0; i < outline.size(); ++i) CHECK(again[i].id == outline[i].id);
    // What a later edit adds gets an id no element had.
    const Outcome added = session.apply(op(R"({"op": "add-primitive", "shape": "cube"})"));
    CHECK_FALSE(oldIds.count(added.added.at(0).number));
    CHECK(added.added.at(0).number != after.at(-10));
}

TEST_CASE("The viewer's editor: a save does not replace a file changed on disk since it was read, and a stale revision "
          "is refused",
          "[edit-history]") {
    const fs::path file = scratchFolder("editor") / "scene.xml";
    writeFile(file, sceneOf(spheres(3)));
    SceneEditor editor(file, quiet());
    editor.operate(parseTypedJson(R"({"op": "set", "node": "object-0", "fields": {"shininess": 9}})"), Camera{});
    SECTION("changed elsewhere: refused, then overwritten when asked") {
        const std::string theirs = sceneOf(spheres(4));
        writeFile(file, theirs);
        CHECK_THROWS_AS(editor.save(), ChangedOnDisk);
        CHECK(readFile(file) == theirs);
        CHECK(editor.modified());
        editor.save(std::nullopt, false, true);
        CHECK(readFile(file) != theirs);
        CHECK_FALSE(editor.modified());
        // Its own save is no change: the next save goes through.
        editor.operate(parseTypedJson(R"({"op": "set", "node": "object-1", "fields": {"shininess": 4}})"), Camera{});
        CHECK_NOTHROW(editor.save());
    }
    SECTION("same size, other bytes") {
        std::string theirs = readFile(file);
        theirs[theirs.find("0.5") + 2] = '6';  // a grey of 0.5 made 0.6: one byte
        writeFile(file, theirs);
        CHECK_THROWS_AS(editor.save(), ChangedOnDisk);
        CHECK(readFile(file) == theirs);
    }
    SECTION("touched, the same bytes: saved") {
        fs::last_write_time(file, fs::file_time_type::clock::now() + std::chrono::seconds(5));
        CHECK_NOTHROW(editor.save());
    }
    SECTION("reloaded: saved") {
        writeFile(file, sceneOf(spheres(5)));
        editor.reload();
        CHECK_NOTHROW(editor.save());
    }
    SECTION("revisions") {
        const uint64_t revision = editor.version();
        CHECK_NOTHROW(editor.checkRevision({{"revision", revision}}));
        CHECK_NOTHROW(editor.checkRevision(nlohmann::json::object()));  // none: not checked
        CHECK_THROWS_AS(editor.checkRevision({{"revision", revision - 1}}), StaleRevision);
        CHECK_THROWS_AS(editor.checkRevision({{"revision", "1"}}), EditError);
        editor.undo();
        CHECK_THROWS_AS(editor.checkRevision({{"revision", revision}}), StaleRevision);
        CHECK(editor.historyJson()["steps"] == 1);
    }
}

TEST_CASE("The C++ API's save does not replace a file changed since it was loaded or saved, unless told",
          "[edit-history]") {
    const fs::path folder = scratchFolder("api");
    const fs::path file = folder / "scene.xml";
    writeFile(file, sceneOf(spheres(2)));
    api::Scene scene = api::Scene::load(file).scene;
    scene.setCamera(scene.camera());
    const std::string theirs = sceneOf(spheres(3));
    writeFile(file, theirs);
    CHECK_THROWS_AS(scene.save(file), api::InputError);
    CHECK(readFile(file) == theirs);
    CHECK_NOTHROW(scene.save(folder / "other.xml"));  // another file: written
    scene.save(file, ray::api::WriteOptions{.overwriteChanges = true});
    CHECK(readFile(file) != theirs);
    CHECK_NOTHROW(scene.save(file));  // its own save is no change
    writeFile(folder / "other.xml", theirs);
    CHECK_THROWS_AS(scene.save(folder / "other.xml"), api::InputError);  // a file it wrote, changed since
}
