// Edits of the scene document's structure: what a modeler adds, removes, moves and
// renames. Each changes the document alone, checked whole before anything changes (a bad
// one throws InputError and leaves the document as it was); a save then writes it into the
// file's text as the few lines it touched (document_splices.h). Fields of a node (a
// material, a light, the camera) are set on the document directly.
//
// What each is in the text: addPrimitive and duplicateObject insert an element (as do
// addLight, and removeLight deletes one: scene_document.h); removeObject deletes one;
// groupIntoTransblock moves elements into a new parent; renameTree changes attributes;
// setTexture adds an element, or changes and adds attributes.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene_document.h"

namespace ray {

// A primitive of `type` in a transblock of its own, with `transforms`, at the end of the
// root tree; returns its id. Throws InputError for a singular transform or a mesh (which
// needs its file: not yet an edit).
int addPrimitive(SceneDocument& document, PrimitiveType type, const Material& material,
                 const std::vector<TransformOp>& transforms);

// Object `id` removed from its transblock (the transblock stays, with what else it holds).
void removeObject(SceneDocument& document, int id);

// A copy of object `id` (its material and files), placed where it is: right after it in
// its transblock. Returns the copy's id.
int duplicateObject(SceneDocument& document, int id);

// The objects `ids`, which must share a transblock, moved into a new transblock (inside an
// inline tree, where the first of them was) with no transforms: a group to transform as one.
// Returns the new transblock's id.
int groupIntoTransblock(SceneDocument& document, const std::vector<int>& ids);

// The top-level tree `from` named `to`, and every master placing it.
void renameTree(SceneDocument& document, const std::string& from, const std::string& to);

// Object `id` textured with `file` (an image; found relative to the document's folder
// when relative), repeated u by v times.
void setTexture(SceneDocument& document, int id, const std::filesystem::path& file, double repeatU, double repeatV);

}  // namespace ray
