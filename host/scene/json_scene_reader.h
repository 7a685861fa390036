// The course's JSON scenefiles (CS1230, 2023 on; SPEC §7) into the scene document the XML
// reader builds (scene_document.h), so that everything after loading (flattening, the
// renderers, the edit model, explain) is the same code for both formats.
//
// How the JSON maps onto the document:
//  - the scene's top-level groups are the blocks of the tree named "root"; each template
//    (templateGroups) is a top-level tree of its own, as an XML master is;
//  - a group is a block: its transforms in the order T, R, S, Matrix whatever the order of
//    its keys (M = M_parent · T · R · S · Matrix), then its primitives, then its subgroups
//    (one inline tree holding a block for each); a group whose name is a template's is a
//    block holding a reference to that template, its other keys ignored (SPEC §7);
//  - lights are the document's world-space lights: each is placed by the transforms of the
//    groups around it, once for every time its template is placed, in the order of the
//    groups (a group's own lights before its subgroups').
// Each node keeps the JSON value it came from (its SourceId is the value's index in the
// tree; SceneDocument::lightSources each light's), so that a save can keep the file
// (json_splices.h).
//
// Every rule of SPEC §7 is checked, each error naming line and column ("scene.json:14:9:")
// and the place in the file's terms ("groups[2].primitives[0]"): an unknown key, a key
// given twice, a value of the wrong type or length, a required key missing, an unknown
// primitive or light type, a camera with both or neither of look and focus, a template
// named twice, a template that contains itself (directly or through others), a missing
// mesh file. What the course's reader gets wrong (SPEC §7's quirks) is not copied:
// templates may be named before they are defined, a cycle is an error and not a hang,
// duplicate template names and a camera without a direction are errors, and a texture
// repeat that is not a number is an error rather than 1.
//
// Paths (meshFile, textureFile, bumpMapFile) are relative to the folder above the scene's
// folder (the course's layout), then found by SPEC §1's search (scene/file_search.h).
//
// Choices the spec leaves open:
//  - A template named "root" is refused: ray's document names the scene's tree so.
//  - Keys that do not apply to a light's type (a point light's "direction") are read,
//    checked and unused, as the course's reader accepts them.
//  - At most kMaxJsonLights lights after templates are placed: a few lines of templates
//    could otherwise place millions.
#pragma once

#include <string_view>

#include "scene/scene_loader_passes.h"

namespace ray {

// How deep arrays and objects may nest in a JSON scene: a group is two levels (the
// "groups" array and the group), so groups can reach kMaxNestingLevels, whose message
// speaks of groups, before this.
constexpr int kMaxJsonDepth = 2 * kMaxNestingLevels + 8;
constexpr size_t kMaxJsonLights = 65536;

namespace loader {

// Reads the JSON text of `document.file` into `document` (its file set by the caller).
// Throws InputError, through `diagnostics`.
void readJsonSceneDocument(std::string_view text, const Diagnostics& diagnostics, SceneDocument& document);

}  // namespace loader
}  // namespace ray
