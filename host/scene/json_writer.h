// The course's JSON text of a scene document (SPEC §7), in the course's style: two blanks of
// indentation a level, an array of numbers on one line, keys in the order the course's files
// write them (json_fields.h), numbers in the shortest form that reads back as the same
// double. What it writes passes the course reader's key rules (every required key, no other
// key) and loads back, in ray, to the same image.
//
// How the document maps onto JSON:
//  - the tree "root" is the scene's "groups", a group for each of its blocks; every other
//    top-level tree (an XML master) is a template ("templateGroups"), and a reference to it
//    a group named as it ({"name": "gear"}), which the reader takes for the template; a
//    template comes after those it places (the course's reader looks only backwards);
//  - a block is a group: its transforms, then its primitives, then its other items as
//    subgroups (an inline tree's blocks, a template's placement, and primitives that follow
//    those, each run of them in a group of its own, so that every primitive keeps its place
//    in the order of the scene's objects). A JSON group applies its transforms as T·R·S·Matrix
//    whatever their order, one of each kind: a block whose transforms are not in that order
//    (or repeat a kind) becomes nested groups, each a run of its transforms that is; a block
//    that holds nothing (no primitive, no placement, in it or its inline trees) is left out,
//    as it adds nothing to the image (a JSON group of lights alone reads as one);
//  - the document's lights are in world space: each is a group of its own before the
//    scene's groups, with a translate to the light's position (point and spot lights) and
//    its direction as it is;
//  - file names (textures, bump maps, meshes) are written relative to the folder above the
//    target's folder, where the course's reader looks for them.
//
// What JSON has no key for is refused, never dropped: a torus, a csg object, an area light,
// emissive colour, a spot light's radius, motion blur (<motion>), a master that names no
// tree, a tree with an empty name. The sentence names the feature and its line in the file
// the document was read from (jsonGaps).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/canonical_writer.h"
#include "scene/scene_document.h"

namespace ray {

// One thing in a document that the course's JSON cannot hold.
struct JsonGap {
    int line = 0;         // in the file the document was read from; 0 when none (made in code)
    std::string feature;  // "a torus (object 4)"
    std::string remedy;   // "replace it with a mesh, or keep the scene in XML"
};

// Every such thing in the document: the lights', then the trees' in the file's order.
std::vector<JsonGap> jsonGaps(const SceneDocument& document);

// The error for `gaps` (not empty): "scene.xml:12: error: a torus (object 4) has no JSON
// key (SPEC §7); replace it ...", and how many more there are, with their lines.
std::string jsonGapsMessage(const SceneDocument& document, const std::vector<JsonGap>& gaps);

class JsonWriter {
public:
    // `target`: the file the text will be written to (file names are written relative to the
    // folder above its folder). `style`: the line break and the indentation step.
    JsonWriter(const SceneDocument& document, const Resources& resources, const std::filesystem::path& target,
               TextStyle style = {});

    // The whole document, with a line break at its end. Throws InputError (jsonGapsMessage)
    // when the document holds what JSON cannot, or a file made in memory.
    std::string document();

    // Entry points for writing one part of a scene into JSON text (a new group, primitive or
    // light spliced into a file's text): each is written as it would be at `indent`: its
    // first line not indented (the caller places it), the next ones indented from `indent`,
    // no line break at its end. Each throws InputError, with jsonGapsMessage's sentence, for
    // what of its part JSON cannot hold.
    //
    // A block as one group (nested groups when its transforms are not in T, R, S, Matrix
    // order), what it holds with it.
    std::string group(const Block& block, const std::string& indent);
    // A primitive object, {"type": "cube", ...}: the fields that differ from a default
    // material's (and a transparent one's "ior", whose default the course's reader takes as 0).
    std::string primitive(const PrimitiveNode& node, const std::string& indent);
    // Light `index` of the document as an object of a group's "lights", {"type": "point",
    // ...}: its direction as the document holds it (world space), no position.
    std::string light(size_t index, const std::string& indent);
    // The group that places light `index`: {"translate": [position], "lights": [light]}
    // (a directional light: no translate).
    std::string lightGroup(size_t index, const std::string& indent);
    // A top-level tree other than "root" as an object of "templateGroups".
    std::string templateGroup(const NamedTree& tree, const std::string& indent);
    std::string globals(const std::string& indent);  // the "globalData" object
    std::string camera(const std::string& indent);   // the "cameraData" object

private:
    // A JSON member: its key and its value's text.
    using Members = std::vector<std::pair<std::string, std::string>>;

    std::string object(const Members& members, const std::string& indent) const;
    std::string array(const std::vector<std::string>& values, const std::string& indent) const;
    std::string deeper(const std::string& indent) const { return indent + style_.indentUnit; }
    std::string number(const std::string& key, double value) const;
    std::string triple(const std::string& owner, const char* element, const Vec3& v) const;
    std::string transformValue(const Block& block, size_t index, const std::string& indent) const;
    Members contentMembers(const Block& block, const std::string& indent);
    std::string nestedGroup(const Block& block, size_t run, const std::vector<size_t>& runStarts,
                            const std::string& name, const std::string& indent);
    std::string namedGroup(const Block& block, const std::string& name, const std::string& indent);
    void refuseGaps(std::vector<JsonGap> gaps) const;

    const SceneDocument& document_;
    const Resources& resources_;
    FileReferences references_;
    TextStyle style_;
};

// The JSON text of the document for `target` (JsonWriter::document).
std::string documentToJson(const SceneDocument& document, const Resources& resources,
                           const std::filesystem::path& target);

// `text` as a JSON string, in double quotes, escaped. Throws InputError, naming `what` the
// text is ("texture file"), for bytes that are not UTF-8 (a JSON file is UTF-8).
std::string jsonString(const std::string& text, const std::string& what);

}  // namespace ray
