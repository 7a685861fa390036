// A save that keeps the file (scene/document_splices.h): unedited, a document saves to its
// file's bytes; edited, to the file with the lines of what the edit touched changed alone;
// and what it saves loads back to the scene the edit made in memory.
#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/canonical_writer.h"
#include "scene/document_edits.h"
#include "scene/scene_document.h"
#include "scene/scene_loader.h"
#include "scene/text_encoding.h"
#include "scene/value_text.h"
#include "scene_comparison.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace ray;
using namespace ray::test;

LoadOptions quiet() { return ray::test::quietLoadOptions(false); }

std::string bytesOf(const fs::path& file) { return ray::test::fileText(file); }

std::vector<std::string> linesOf(const std::string& text) { return ray::test::textLines(text); }

// A line diff of two texts: the lines of `before` (1-based, first and last) between the
// lines both begin and end with ({0, 0} when they have the same lines; an insertion
// touches the line it follows), and how many lines a diff removes and adds there (those
// of the window less their longest common subsequence).
struct LineDiff {
    size_t first = 0, last = 0, changedBefore = 0, changedAfter = 0;
    size_t removed = 0, added = 0;
};

size_t longestCommonSubsequence(const std::vector<std::string>& a, const std::vector<std::string>& b) {
    std::vector<std::vector<size_t>> length(a.size() + 1, std::vector<size_t>(b.size() + 1, 0));
    for (size_t i = 1; i <= a.size(); ++i)
        for (size_t j = 1; j <= b.size(); ++j)
            length[i][j] = a[i - 1] == b[j - 1] ? length[i - 1][j - 1] + 1 : std::max(length[i - 1][j], length[i][j - 1]);
    return length[a.size()][b.size()];
}

LineDiff lineDiff(const std::string& before, const std::string& after) {
    const std::vector<std::string> a = linesOf(before), b = linesOf(after);
    size_t prefix = 0;
    while (prefix < a.size() && prefix < b.size() && a[prefix] == b[prefix]) ++prefix;
    size_t suffix = 0;
    while (suffix < a.size() - prefix && suffix < b.size() - prefix &&
           a[a.size() - 1 - suffix] == b[b.size() - 1 - suffix])
        ++suffix;
    LineDiff diff;
    diff.changedBefore = a.size() - prefix - suffix;
    diff.changedAfter = b.size() - prefix - suffix;
    if (diff.changedBefore == 0 && diff.changedAfter == 0) return diff;
    const std::vector<std::string> windowBefore(a.begin() + std::ptrdiff_t(prefix), a.end() - std::ptrdiff_t(suffix)),
        windowAfter(b.begin() + std::ptrdiff_t(prefix), b.end() - std::ptrdiff_t(suffix));
    const size_t common = longestCommonSubsequence(windowBefore, windowAfter);
    diff.removed = windowBefore.size() - common;
    diff.added = windowAfter.size() - common;
    // An insertion between lines p and p+1 is said to touch line p (the line it follows).
    diff.first = diff.changedBefore ? prefix + 1 : prefix;
    diff.last = diff.changedBefore ? prefix + diff.changedBefore : prefix;
    return diff;
}

// The lines (1-based, first and last) element `id` of the document's text spans.
std::pair<size_t, size_t> linesOfElement(const SourceText& text, SourceId id) {
    const std::string& bytes = text.bytes();
    const XmlSpan& span = text.span(id);
    const auto first = size_t(std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(span.begin), '\n')) + 1;
    const auto last = size_t(std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(span.end), '\n')) + 1;
    return {first, last};
}

// The scene the edited document saves to, loaded back, against the one it flattens to.
void checkReloads(SceneDocument& edited, const std::string& text) {
    Resources resources;
    const Scene inMemory = flattenDocument(edited, resources, quiet());
    const Scene reloaded = loadSceneFromText(text, edited.file, quiet());
    // Ids are given afresh on loading, in the file's order: an object removed or added
    // in memory numbers the others differently.
    CHECK(sameInstances(inMemory.primitives, reloaded.primitives, IdsToo::No));
    CHECK(sameInstances(inMemory.csgOperands, reloaded.csgOperands, IdsToo::No));
    CHECK(sameTables(inMemory, reloaded));
}

// Saves `edited`, and checks that the text differs from the file's within `element`'s
// lines alone, and loads back to the edited scene. Returns the diff.
LineDiff checkEdit(SceneDocument& edited, SourceId element) {
    Resources resources;
    const std::string& original = edited.source->bytes();
    const std::string text = documentToText(edited, resources, edited.file);
    const LineDiff diff = lineDiff(original, text);
    const auto [first, last] = linesOfElement(*edited.source, element);
    INFO("changed lines " << diff.first << "-" << diff.last << "; the element's " << first << "-" << last);
    CHECK(diff.changedAfter > 0);
    CHECK(diff.first >= first);
    CHECK(diff.last <= last);
    checkReloads(edited, text);
    return diff;
}

struct Sizes {
    size_t edits = 0, removed = 0, added = 0, mostRemoved = 0, mostAdded = 0;
    void add(const LineDiff& d) {
        ++edits, removed += d.removed, added += d.added;
        mostRemoved = std::max(mostRemoved, d.removed), mostAdded = std::max(mostAdded, d.added);
    }
    std::string said(const char* what) const {
        std::ostringstream out;
        const double n = double(std::max<size_t>(edits, 1));
        out << what << ": " << edits << " scenes, a diff of -" << double(removed) / n << " +" << double(added) / n
            << " lines on average (at most -" << mostRemoved << " +" << mostAdded << ")";
        return out.str();
    }
};

// The first object of the document that its file writes (in document order).
PrimitiveNode* firstWrittenObject(SceneDocument& document) {
    PrimitiveNode* found = nullptr;
    forEachObject(document, [&](PrimitiveNode& node, const DocumentPlace&) {
        if (!found && node.source != kNoSource) found = &node;
    });
    return found;
}

Block* firstWrittenBlock(SceneDocument& document) {
    Block* found = nullptr;
    forEachBlock(document, [&](Block& block, const DocumentPlace&) {
        if (!found && block.source != kNoSource) found = &block;
    });
    return found;
}

}  // namespace

TEST_CASE("every course scene that loads saves unedited to its own bytes, and edited to its lines alone",
          "[document][text][corpus]") {
    std::optional<fs::path> shared = sharedDir();
    if (!shared) {
        skip("../shared/cs123 is absent: the course corpus is not here");
        return;
    }
    const auto start = std::chrono::steady_clock::now();
    int loaded = 0, identical = 0;
    Sizes material, light, transform, camera;
    for (const fs::path& file : courseScenes(*shared)) {
        INFO(file.filename().string());
        SceneDocument document;
        try {
            document = loadSceneDocument(file, quiet());
            Resources resources;
            flattenDocument(document, resources, quiet());
        } catch (const InputError&) {
            continue;  // the corpus tests hold these to their messages
        }
        ++loaded;
        Resources resources;
        const std::string text = documentToText(document, resources, file);
        CHECK(text == bytesOf(file));
        identical += text == bytesOf(file) ? 1 : 0;

        if (SceneDocument edited = document; PrimitiveNode* node = firstWrittenObject(edited)) {
            node->material.diffuse = {0.12549019607843137, 0.5, 1.0 / 3};  // a picked color, not 8 bits
            node->material.shininess += 1;
            material.add(checkEdit(edited, node->source));
        }
        if (SceneDocument edited = document; !edited.lights.empty() && !edited.lightSources.empty()) {
            edited.lights[0].color = {0.25, 0.5, 0.75};
            edited.lights[0].position += Vec3{1, 0, 0};
            light.add(checkEdit(edited, edited.lightSources[0]));
        }
        if (SceneDocument edited = document; Block* block = firstWrittenBlock(edited)) {
            if (block->transforms.empty())
                block->transforms.push_back({TransformKind::Translate, {0.5, 0, 0}});
            else
                block->transforms.front().v[0] += 0.5;
            composeBlock(*block);
            transform.add(checkEdit(edited, block->source));
        }
        if (SceneDocument edited = document; true) {
            edited.camera.position += Vec3{0, 0.25, 0};
            edited.camera.heightAngleDegrees = 40;
            const XmlElement root = edited.source->tree().root();
            SourceId cameradata = kNoSource;
            for (XmlElement c = root.firstChild(); c; c = c.nextSibling())
                if (sameName(c.name(), "cameradata")) cameradata = c.index();
            if (cameradata != kNoSource) camera.add(checkEdit(edited, cameradata));
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << loaded << " course scenes load; " << identical << " save unedited to their own bytes (" << seconds
              << " s with the edits)\n"
              << material.said("material") << "\n"
              << light.said("light") << "\n"
              << transform.said("transform") << "\n"
              << camera.said("camera") << "\n";
    CHECK(loaded == 211);
    CHECK(identical == loaded);
}

namespace {

// A hand-written file: comments, single quotes, blanks inside tags, a <focus> point, an
// <aspectratio> the loader ignores, a bare object, numbers as people write them.
const char* kHandWritten = R"(<?xml version="1.0"?>
<!-- a table, by hand -->
<scenefile>
	<globaldata>
		<ambientcoeff v = '0.50'/>
	</globaldata>
	<cameradata>
		<pos x="0" y="1.0" z="6" />
		<focus x="0" y="1" z="0"/>
		<up x="0" y="1" z="0"/>
		<aspectratio v="1.3333"/>
	</cameradata>
	<lightdata>
		<id v="0"/>
		<type v="POINT"/>
		<color r="1" g="1" b="1"/>  <!-- white -->
		<position x="3" y="4" z="5"/>
	</lightdata>
	<lightdata><id v="1"/><type v="directional"/><color r=".5" g=".5" b=".5"/><direction x="0" y="-1" z="0"/></lightdata>
	<object type="tree" name="leg">
		<transblock>
			<scale x="0.2" y="2" z="0.2"/>
			<object type="primitive" name="cylinder">
				<diffuse r="0.8" g="0.5" b="0.2"/>
			</object>
		</transblock>
	</object>
	<object type="tree" name="root">
		<!-- the legs -->
		<transblock><translate x="-1" y="0" z="0"/><object type="master" name="leg"/></transblock>
		<transblock><translate x="1" y="0" z="0"/><object type="master" name="leg"/></transblock>
		<transblock>
			<translate x="0" y="1.5" z="0"/>
			<object type="primitive" name="sphere">
				<diffuse r="0.2" g="0.3" b="0.9"/>
				<shininess v="20"/>
			</object>
			<object type="primitive" name="cube"/>
		</transblock>
		<object type="primitive" name="cone"/>
	</object>
</scenefile>
)";

struct Edited {
    SceneDocument document;
    std::string original;

    explicit Edited(const std::string& text) : original(text) {
        document = loadSceneDocumentFromText(text, fs::path(RAY_TEST_SCENES_DIR) / "hand.xml", quiet());
    }
    std::string saved() const {
        Resources resources;
        return documentToText(document, resources, document.file);
    }
    int objectOfType(PrimitiveType type) {
        int id = -1;
        forEachObject(document, [&](PrimitiveNode& node, const DocumentPlace&) {
            if (id < 0 && node.type == type) id = node.id;
        });
        return id;
    }
    PrimitiveNode& object(int id) {
        std::optional<DocumentPlace> place = findObject(document, id);
        REQUIRE(place);
        return std::get<PrimitiveNode>(place->block->items[place->item]);
    }
    // The saved text against the original, both from the line where they part.
    std::string change() const {
        const std::string after = saved();
        size_t prefix = 0;
        while (prefix < original.size() && prefix < after.size() && original[prefix] == after[prefix]) ++prefix;
        return after.substr(original.rfind('\n', prefix) + 1);
    }
};

// `original` with its first `from` replaced by `to`.
std::string replaced(const std::string& original, const std::string& from, const std::string& to) {
    const size_t at = original.find(from);
    REQUIRE(at != std::string::npos);
    return original.substr(0, at) + to + original.substr(at + from.size());
}

}  // namespace

TEST_CASE("a save keeps what no edit touched and writes each edit where it belongs", "[document][text]") {
    Edited edit(kHandWritten);

    SECTION("unedited, the file byte for byte") { CHECK(edit.saved() == kHandWritten); }

    SECTION("a changed number is written inside its own quotes, the others as written") {
        edit.document.globals.ka = 0.25;
        CHECK(edit.saved() == replaced(kHandWritten, "v = '0.50'", "v = '0.25'"));
    }

    SECTION("a number typed by the user is written as typed; a picked one in the shortest exact form") {
        PrimitiveNode& sphere = edit.object(edit.objectOfType(PrimitiveType::Sphere));
        sphere.material.shininess = 25;
        setTypedNumber(edit.document, numberKey("object " + std::to_string(sphere.id), "shininess", 0), "25.0");
        sphere.material.diffuse.x = 0.12549019607843137;
        std::string expected = replaced(kHandWritten, "<shininess v=\"20\"/>", "<shininess v=\"25.0\"/>");
        expected = replaced(expected, "<diffuse r=\"0.2\" g=\"0.3\"", "<diffuse r=\"0.12549019607843137\" g=\"0.3\"");
        CHECK(edit.saved() == expected);
        // A typed text that no longer reads as the value is not written.
        sphere.material.shininess = 30;
        CHECK(edit.saved().find("<shininess v=\"30\"/>") != std::string::npos);
        CHECK_THROWS_AS(setTypedNumber(edit.document, "camera pos 0", "1,5"), InputError);
    }

    SECTION("a field the element lacks is added on a line of its own, indented like its siblings") {
        PrimitiveNode& cylinder = edit.object(edit.objectOfType(PrimitiveType::Cylinder));
        cylinder.material.specular = {0.5, 0.5, 0.5};
        CHECK(edit.saved() == replaced(kHandWritten, "<diffuse r=\"0.8\" g=\"0.5\" b=\"0.2\"/>\n",
                                       "<diffuse r=\"0.8\" g=\"0.5\" b=\"0.2\"/>\n\t\t\t\t<specular r=\"0.5\" "
                                       "g=\"0.5\" b=\"0.5\"/>\n"));
    }

    SECTION("a self-closing object given a field opens, and closes on its own line") {
        PrimitiveNode& cube = edit.object(edit.objectOfType(PrimitiveType::Cube));
        cube.material.shininess = 4;
        CHECK(edit.saved() == replaced(kHandWritten, "\t\t\t<object type=\"primitive\" name=\"cube\"/>\n",
                                       "\t\t\t<object type=\"primitive\" name=\"cube\">\n\t\t\t\t<shininess "
                                       "v=\"4\"/>\n\t\t\t</object>\n"));
    }

    SECTION("a camera moved keeps its focus point while the point reads as its direction") {
        // The camera keeps its direction, so the point it looks at moves with it.
        edit.document.camera.position.y = 2;
        CHECK(edit.saved() == replaced(replaced(kHandWritten, "y=\"1.0\" z=\"6\" />", "y=\"2\" z=\"6\" />"),
                                       "<focus x=\"0\" y=\"1\" z=\"0\"/>", "<focus x=\"0\" y=\"2\" z=\"0\"/>"));
        checkReloads(edit.document, edit.saved());
        edit.document.camera.look = {0, 0, -1};
        CHECK(edit.change().find("<focus x=\"0\" y=\"2\" z=\"5\"/>") != std::string::npos);
        checkReloads(edit.document, edit.saved());
    }

    SECTION("a light's type is compared as the loader reads it, and set as the format spells it") {
        CHECK(edit.document.lights[0].type == LightType::Point);
        edit.document.lights[0].type = LightType::Spot;
        CHECK(edit.saved() == replaced(kHandWritten, "<type v=\"POINT\"/>", "<type v=\"spot\"/>"));
    }

    SECTION("a transform list replaced by one of other kinds: the old ones go, the new ones come in their place") {
        std::optional<DocumentPlace> place = findObject(edit.document, edit.objectOfType(PrimitiveType::Sphere));
        Block& block = *place->block;
        block.transforms = {TransformOp::matrix(Affine::translation({0, 2, 0}))};
        composeBlock(block);
        CHECK(edit.change().rfind("\t\t\t<matrix>\n\t\t\t\t<row0 v1=\"1\" v2=\"0\" v3=\"0\" v4=\"0\"/>", 0) == 0);
        CHECK(edit.saved().find("<translate x=\"0\" y=\"1.5\"") == std::string::npos);
        checkReloads(edit.document, edit.saved());
    }

    SECTION("a bare object given a transform is put in a transblock of its own") {
        std::optional<DocumentPlace> place = findObject(edit.document, edit.objectOfType(PrimitiveType::Cone));
        place->block->transforms = {{TransformKind::Translate, {0, 0, 2}}};
        composeBlock(*place->block);
        CHECK(edit.saved() == replaced(kHandWritten, "\t\t<object type=\"primitive\" name=\"cone\"/>\n",
                                       "\t\t<transblock>\n\t\t\t<translate x=\"0\" y=\"0\" z=\"2\"/>\n\t\t\t<object "
                                       "type=\"primitive\" name=\"cone\"/>\n\t\t</transblock>\n"));
        checkReloads(edit.document, edit.saved());
    }
}

TEST_CASE("the document's edits of structure are splices: insert, delete, move, change and add attributes",
          "[document][text]") {
    Edited edit(kHandWritten);

    SECTION("add a primitive: a transblock after the root's last, indented like it") {
        Material red;
        red.diffuse = {1, 0, 0};
        addPrimitive(edit.document, PrimitiveType::Torus, red, {{TransformKind::Scale, {2, 2, 2}}});
        CHECK(edit.saved() == replaced(kHandWritten, "\t\t<object type=\"primitive\" name=\"cone\"/>\n",
                                       "\t\t<object type=\"primitive\" name=\"cone\"/>\n\t\t<transblock>\n\t\t\t<scale "
                                       "x=\"2\" y=\"2\" z=\"2\"/>\n\t\t\t<object type=\"primitive\" "
                                       "name=\"torus\">\n\t\t\t\t<diffuse r=\"1\" g=\"0\" b=\"0\"/>\n\t\t\t</object>\n"
                                       "\t\t</transblock>\n"));
        checkReloads(edit.document, edit.saved());
        CHECK_THROWS_AS(addPrimitive(edit.document, PrimitiveType::Sphere, red, {{TransformKind::Scale, {0, 1, 1}}}),
                        InputError);
    }

    SECTION("add a light: after the last, as the file indents") {
        Light spot;
        spot.type = LightType::Spot;
        spot.direction = {0, -1, 0};
        spot.angleDegrees = 30;
        CHECK(addLight(edit.document, spot) == 2);
        CHECK(edit.change().rfind("\t<lightdata>\n\t\t<id v=\"2\"/>\n\t\t<type v=\"spot\"/>\n", 0) == 0);
        checkReloads(edit.document, edit.saved());
    }

    SECTION("remove a light: its lines go, the comment above the trees stays") {
        removeLight(edit.document, 1);
        const std::string light =
            "\t<lightdata><id v=\"1\"/><type v=\"directional\"/><color r=\".5\" g=\".5\" b=\".5\"/><direction x=\"0\" "
            "y=\"-1\" z=\"0\"/></lightdata>\n";
        CHECK(edit.saved() == replaced(kHandWritten, light, ""));
        // The light after a removed one keeps its own element.
        Edited first(kHandWritten);
        removeLight(first.document, 0);
        first.document.lights[0].color = {0.25, 0.25, 0.25};
        CHECK(first.saved().find("<color r=\"0.25\" g=\"0.25\" b=\"0.25\"/><direction") != std::string::npos);
        CHECK(first.saved().find("<type v=\"POINT\"/>") == std::string::npos);
        CHECK_THROWS_AS(removeLight(first.document, 5), InputError);
    }

    SECTION("remove an object: its own lines go") {
        removeObject(edit.document, edit.objectOfType(PrimitiveType::Cube));
        CHECK(edit.saved() == replaced(kHandWritten, "\t\t\t<object type=\"primitive\" name=\"cube\"/>\n", ""));
        checkReloads(edit.document, edit.saved());
    }

    SECTION("duplicate an object: the copy follows it, written afresh") {
        const int copy = duplicateObject(edit.document, edit.objectOfType(PrimitiveType::Sphere));
        CHECK(copy == edit.document.nextObjectId - 1);
        CHECK(edit.saved() == replaced(kHandWritten, "\t\t\t</object>\n\t\t\t<object type=\"primitive\" name=\"cube\"/>",
                                       "\t\t\t</object>\n\t\t\t<object type=\"primitive\" name=\"sphere\">\n\t\t\t\t<diffuse "
                                       "r=\"0.2\" g=\"0.3\" b=\"0.9\"/>\n\t\t\t\t<shininess v=\"20\"/>\n\t\t\t</object>"
                                       "\n\t\t\t<object type=\"primitive\" name=\"cube\"/>"));
        checkReloads(edit.document, edit.saved());
    }

    SECTION("group into a transblock: the objects move, their text and edits with them, indented a step deeper") {
        const int sphere = edit.objectOfType(PrimitiveType::Sphere), cube = edit.objectOfType(PrimitiveType::Cube);
        edit.object(sphere).material.shininess = 21;
        groupIntoTransblock(edit.document, {sphere, cube});
        CHECK(edit.saved() ==
              replaced(kHandWritten,
                       "\t\t\t<object type=\"primitive\" name=\"sphere\">\n\t\t\t\t<diffuse r=\"0.2\" g=\"0.3\" "
                       "b=\"0.9\"/>\n\t\t\t\t<shininess v=\"20\"/>\n\t\t\t</object>\n\t\t\t<object type=\"primitive\" "
                       "name=\"cube\"/>\n",
                       "\t\t\t<object type=\"tree\">\n\t\t\t\t<transblock>\n\t\t\t\t\t<object type=\"primitive\" "
                       "name=\"sphere\">\n\t\t\t\t\t\t<diffuse r=\"0.2\" g=\"0.3\" b=\"0.9\"/>\n\t\t\t\t\t\t<shininess "
                       "v=\"21\"/>\n\t\t\t\t\t</object>\n\t\t\t\t\t<object type=\"primitive\" name=\"cube\"/>\n"
                       "\t\t\t\t</transblock>\n\t\t\t</object>\n"));
        checkReloads(edit.document, edit.saved());
        CHECK_THROWS_AS(groupIntoTransblock(edit.document, {sphere, edit.objectOfType(PrimitiveType::Cone)}),
                        InputError);
    }

    SECTION("rename a tree: its name and every master's change, nothing else") {
        renameTree(edit.document, "leg", "post");
        std::string expected = replaced(kHandWritten, "name=\"leg\">", "name=\"post\">");
        expected = replaced(expected, "name=\"leg\"/>", "name=\"post\"/>");
        expected = replaced(expected, "name=\"leg\"/>", "name=\"post\"/>");
        CHECK(edit.saved() == expected);
        checkReloads(edit.document, edit.saved());
        CHECK_THROWS_AS(renameTree(edit.document, "post", "root"), InputError);
        CHECK_THROWS_AS(renameTree(edit.document, "leg", "table"), InputError);
    }

    SECTION("set a texture: an element added, then its file changed and its repeats added as attributes") {
        const fs::path scenes = RAY_TEST_SCENES_DIR;
        const int cylinder = edit.objectOfType(PrimitiveType::Cylinder);
        setTexture(edit.document, cylinder, "textures/checker.png", 1, 1);
        CHECK(edit.change().rfind("\t\t\t\t<texture file=\"textures/checker.png\" u=\"1\" v=\"1\"/>\n", 0) == 0);
        checkReloads(edit.document, edit.saved());

        const std::string textured = replaced(kHandWritten, "<diffuse r=\"0.8\" g=\"0.5\" b=\"0.2\"/>",
                                              "<diffuse r=\"0.8\" g=\"0.5\" b=\"0.2\"/><texture file='nowhere.png'/>");
        Edited again(textured);
        const int id = again.objectOfType(PrimitiveType::Cylinder);
        CHECK(again.saved() == textured);
        setTexture(again.document, id, scenes / "textures" / "checker.png", 2, 1);
        CHECK(again.saved() == replaced(textured, "<texture file='nowhere.png'/>",
                                        "<texture file='textures/checker.png' u=\"2\"/>"));
        checkReloads(again.document, again.saved());
        CHECK_THROWS_AS(setTexture(again.document, id, "no/such.png", 1, 1), InputError);
        CHECK_THROWS_AS(setTexture(again.document, id, "textures/checker.png", 0, 1), InputError);
    }
}

TEST_CASE("a document with no text saves canonically, CRLF files keep their line breaks", "[document][text]") {
    SECTION("from nothing") {
        SceneDocument document;
        document.file = "new.xml";
        document.camera.position = {0, 0, 5};
        document.camera.look = {0, 0, -1};
        Light light;
        light.position = {1, 2, 3};
        addLight(document, light);
        PrimitiveNode sphere;
        sphere.type = PrimitiveType::Sphere;
        Block block;
        block.items.push_back(sphere);
        document.rootToSet().tree.blocks.push_back(std::move(block));
        Resources resources;
        const std::string text = documentToText(document, resources, "new.xml");
        CHECK(text ==
              "<scenefile>\n  <globaldata>\n    <ambientcoeff v=\"0.5\"/>\n    <diffusecoeff v=\"0.5\"/>\n"
              "    <specularcoeff v=\"0.5\"/>\n    <transparentcoeff v=\"0.5\"/>\n  </globaldata>\n  <cameradata>\n"
              "    <pos x=\"0\" y=\"0\" z=\"5\"/>\n    <look x=\"0\" y=\"0\" z=\"-1\"/>\n    <up x=\"0\" y=\"1\" "
              "z=\"0\"/>\n    <heightangle v=\"45\"/>\n  </cameradata>\n  <lightdata>\n    <id v=\"0\"/>\n    <type "
              "v=\"point\"/>\n    <color r=\"1\" g=\"1\" b=\"1\"/>\n    <function v1=\"1\" v2=\"0\" v3=\"0\"/>\n"
              "    <position x=\"1\" y=\"2\" z=\"3\"/>\n  </lightdata>\n  <object type=\"tree\" name=\"root\">\n"
              "    <transblock>\n      <object type=\"primitive\" name=\"sphere\"/>\n    </transblock>\n"
              "  </object>\n</scenefile>\n");
        SceneDocument reloaded = loadSceneDocumentFromText(text, "new.xml", quiet());
        CHECK(reloaded.camera == document.camera);
        CHECK(documentToText(reloaded, resources, "new.xml") == text);
    }

    SECTION("CRLF") {
        std::string crlf;
        for (char c : std::string(kHandWritten)) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
        Edited edit(crlf);
        CHECK(edit.saved() == crlf);
        edit.object(edit.objectOfType(PrimitiveType::Cylinder)).material.blend = 0.5;
        CHECK(edit.saved() == replaced(crlf, "b=\"0.2\"/>\r\n", "b=\"0.2\"/>\r\n\t\t\t\t<blend v=\"0.5\"/>\r\n"));
    }
}

TEST_CASE("ray's own scenes save unedited to their own bytes, and a csg operand's edit to its lines", "[document][text]") {
    int saved = 0;
    for (const auto& entry : fs::directory_iterator(RAY_TEST_SCENES_DIR)) {
        if (entry.path().extension() != ".xml") continue;
        INFO(entry.path().filename().string());
        SceneDocument document = loadSceneDocument(entry.path(), quiet());
        Resources resources;
        CHECK(documentToText(document, resources, entry.path()) == bytesOf(entry.path()));
        ++saved;
    }
    CHECK(saved > 10);

    SceneDocument csg = loadSceneDocument(fs::path(RAY_TEST_SCENES_DIR) / "csg_die.xml", quiet());
    PrimitiveNode* operand = nullptr;
    forEachObject(csg, [&](PrimitiveNode& node, const DocumentPlace& place) {
        if (!operand && place.path.find("operand") != std::string::npos) operand = &node;
    });
    REQUIRE(operand);
    operand->material.diffuse = {0.1, 0.2, 0.3};
    checkEdit(csg, operand->source);
}

TEST_CASE("a file in UTF-16 is spliced as its text in UTF-8, and saved in UTF-16", "[document][text]") {
    const std::string ascii = "<scenefile><object type=\"tree\" name=\"root\"><transblock><object "
                              "type=\"primitive\" name=\"cube\"/></transblock></object></scenefile>";
    std::string utf16 = "\xFF\xFE";
    for (char c : ascii) utf16 += std::string{c, '\0'};
    SceneDocument document = loadSceneDocumentFromText(utf16, "utf16.xml", quiet());
    REQUIRE(document.source);
    CHECK(document.source->encoding() == TextEncoding::Utf16LE);
    Resources resources;
    CHECK(documentFileBytes(document, resources, "utf16.xml") == utf16);
    CHECK(documentToText(document, resources, "utf16.xml") == "\xEF\xBB\xBF" + ascii);  // the mark as U+FEFF
    document.trees["root"].tree.blocks[0].transforms.push_back(TransformOp{});
    composeBlock(document.trees["root"].tree.blocks[0]);
    const std::string text = documentToText(document, resources, "utf16.xml");
    CHECK(text.find("<translate x=\"0\" y=\"0\" z=\"0\"/>") != std::string::npos);
    checkReloads(document, text);
    CHECK(documentFileBytes(document, resources, "utf16.xml") == fromUtf8(text, TextEncoding::Utf16LE));
}
