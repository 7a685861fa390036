// A node's fields as the field table (field_table.h) describes them: reading a value,
// checking one an edit gives, and setting it in the document. What the editing service
// (edit_session.h) and its operations do to a field goes through here, whichever front end
// asked.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "edit/field_table.h"
#include "edit/node_places.h"
#include "scene/scene.h"
#include "scene/scene_changes.h"
#include "scene/scene_document.h"

namespace ray::edit {

// What a file an edit names is for.
enum class FileUse { Image, Mesh };
// Turns a file name from an edit into the file to read: the viewer keeps it to the scene's
// folder (viewer/folder_files.h); by default it is found from the document's folder.
// Throws EditError (or what it likes: its message is the error's).
using FileResolver = std::function<std::filesystem::path(const std::string& name, FileUse use)>;

// The owner of a node kind's fields; nullopt for a placement or a csg object (none).
std::optional<FieldOwner> fieldOwner(NodeKind kind);
// The fields node `place` shows, in the table's order (a light's of its type alone).
std::vector<const EditField*> fieldsFor(const SceneDocument& document, const NodePlace& place);

// Field `field` of the node at `place`. `scene` (the document flattened) gives an object's
// world matrix.
FieldValue fieldValue(const SceneDocument& document, const Scene& scene, const NodePlace& place,
                      const EditField& field);

// The value's kind and range, by the table: EditError (Type for a wrong kind, Value for a
// value out of range, naming the field) when it is refused.
void checkFieldValue(const FieldInput& input, const std::string& node);

// Text an edit writes into the document (a name, a file name) checked against what the
// scene file can hold (XML 1.0's characters, valid UTF-8: scene/xml_characters.h):
// EditError naming `field` and the character ("name: U+FFFF at character 4 cannot be
// written in an XML file") otherwise, before anything changes.
void checkWritable(std::string_view field, const std::string& text, const std::string& node);

// What setting a field needs besides the document: the files it may read (textures,
// meshes), into `resources`, and the flattened scene as it is (an object's world matrix).
struct FieldContext {
    Resources& resources;
    const Scene& scene;
    const FileResolver& resolveFile;
};

// Sets the field of the node at `place` (checked first: checkFieldValue, then what only the
// document can tell: a texture that does not decode, a name in use). Returns what it changed
// in the flattened scene. The number texts the input was typed as are kept for the save.
// Throws EditError. `place` may be stale afterwards (the document changed).
SceneChanges setField(SceneDocument& document, const NodePlace& place, const FieldInput& input,
                      const FieldContext& context);

// Reads `file` into `resources` as an image (once), so that flattening finds it. Throws
// EditError naming `field` when it does not decode.
void loadImageInto(Resources& resources, const std::filesystem::path& file, const std::string& field);
// The same for an OBJ mesh.
void loadMeshInto(Resources& resources, const std::filesystem::path& file, const std::string& field);

// The object-to-world transform of object `id`'s first instance in `scene`, and its inverse;
// nullopt when it has none (in a master no tree places).
std::optional<std::pair<Affine, Affine>> firstInstancePlacement(const Scene& scene, int id);

}  // namespace ray::edit
