// What a save changes in a course JSON scene's text (SPEC §7): the splices (source_text.h)
// that make the text say what the document says now, as document_splices.h does for XML.
//
// A JSON document keeps its text, the text's tree (json_tree.h, every value's offset) and
// the document as that text reads (JsonSource), and each node keeps the JSON value it was
// read from (its SourceId is the value's JsonValue::index): a primitive its object, a
// group's block its object, a "groups" array's tree the array, a template placement its
// group; each light the light object in its group (a light a template places several
// times is one value placed several times). A save compares each node with what its value
// read as: a number that differs is written over the old one's text (as the user typed it,
// or in the shortest form that reads back as it); a key the object lacks is added on a line
// of its own indented like its neighbours (or after them on their line); a value no node
// claims any more (a removed primitive, group or light) goes with its own lines. Nothing
// else of the text changes: unedited, the file comes back byte for byte.
//
// Lights are world-space in the document and local to their group in the file: a light's
// direction is written in its group's frame, and its position is its group's origin, so a
// light moved on its own is written by moving its group when the group holds nothing else,
// and refused otherwise. What JSON cannot say is refused with the reason (InputError), so
// that the editor refuses the edit before it changes anything (jsonUnsaveable): a torus, an
// area light, an emissive colour, csg, motion, transforms not in the order T, R, S, Matrix
// or twice of a kind, a transformed template placement, an edit of a light a template
// places several times (one value in the file).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "scene/json_tree.h"
#include "scene/scene_document.h"
#include "scene/source_text.h"

namespace ray {

// The JSON text a document was read from (SceneDocument::jsonSource).
struct JsonSource {
    // `text` must be the text `asRead` was read from.
    JsonSource(std::string text, const SceneDocument& asRead);

    std::string text;
    JsonTree tree;
    SceneDocument asRead;           // the document as the text reads: what a save compares with
    std::vector<uint32_t> parents;  // by value index: the array or object holding it (the root: 0)
    std::string newline = "\n";     // the line break the text uses
};

// The splices for `document`, whose jsonSource must be set. Paths the document changed are
// written relative to the folder above `target`'s folder (the course's rule). Throws
// InputError for what the JSON format cannot hold, naming it and its place in the file.
std::vector<Splice> jsonDocumentSplices(const SceneDocument& document, const Resources& resources,
                                        const std::filesystem::path& target);

// A JSON scene's lights are placed by their groups: after an edit moved, placed again or
// removed a group, the lights `before` had where their groups put them are put where the
// groups in `after` put them (a light set on its own stays as it was set). The edit session
// calls it after each operation on a JSON document.
void placeLightsByTheirGroups(const SceneDocument& before, SceneDocument& after);

// Why `document` (read from JSON) cannot be saved as JSON; nullopt when it can: the check
// the editor makes before it keeps an edit.
std::optional<std::string> jsonUnsaveable(const SceneDocument& document, const Resources& resources);

}  // namespace ray
