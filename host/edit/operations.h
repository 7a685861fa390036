// The operations of the one edit model (docs/modeler-protocol.md): what the page, the C++ API
// and Python ask of the editing service (edit_session.h), each applied to a scene document
// whole or not at all, each saying what it changed.
#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "edit/field_table.h"
#include "edit/field_values.h"
#include "edit/node_id.h"
#include "scene/scene_changes.h"
#include "scene/scene_document.h"

namespace ray::edit {

// Sets fields of one node (all or none): a material, a light, the camera, the globals, an
// object's texture or transforms, a transblock's transforms, a tree's name.
struct SetFields {
    NodeId node;
    std::vector<FieldInput> fields;
};

// A primitive in a transblock of its own: at the end of the root tree, or inside transblock
// `parent`. A mesh names its OBJ file (meshFile, found by the session's FileResolver) or a
// mesh made in code (mesh, an index of Resources::meshes). `fields`: the object's (its
// material, texture, transform).
struct AddPrimitive {
    PrimitiveType shape = PrimitiveType::Cube;
    std::string meshFile;
    int mesh = -1;
    std::optional<NodeId> parent;
    std::vector<FieldInput> fields;
};

// A light after the others, of `type`, with `fields` set.
struct AddLight {
    LightType type = LightType::Point;
    std::vector<FieldInput> fields;
};

// Removes objects, lights, transblocks (with all they hold), placements, csg objects and
// masters no placement names.
struct DeleteNodes {
    std::vector<NodeId> nodes;
};

// A copy of each object, transblock, placement, csg object or light, right after it.
struct DuplicateNodes {
    std::vector<NodeId> nodes;
};

// Objects of one transblock moved into a new transblock there, with no transforms.
struct GroupNodes {
    std::vector<NodeId> nodes;
};

// A placement of a master given a copy of the master of its own (Blender's single-user
// copy), named after it ("leg_2"): editing it then changes this placement alone.
struct MakeUnique {
    NodeId placement;
};

using Operation = std::variant<SetFields, AddPrimitive, AddLight, DeleteNodes, DuplicateNodes, GroupNodes, MakeUnique>;

// "set", "add-primitive", "add-light", "delete", "duplicate", "group", "make-unique".
const char* operationName(const Operation& operation);

// What an operation did.
struct Outcome {
    SceneChanges changes;         // in the flattened scene: what a renderer re-packs
    std::vector<NodeId> changed;  // nodes whose fields changed
    std::vector<NodeId> added;    // nodes made (the first is the operation's own: the object, the copy...)
    std::vector<NodeId> removed;  // nodes removed (those named; what they held went with them)
    bool outline = false;         // the tree changed (an add, a delete, a rename, a new transblock)

    // Another operation's outcome after this one, as one step.
    Outcome& operator+=(const Outcome& later);
};

// Applies `operation` to `document`. Throws EditError, leaving `document` part-changed: the
// session applies operations to a copy (edit_session.h).
Outcome perform(SceneDocument& document, const Operation& operation, const FieldContext& context);

// Whether `operation` can be applied to the document itself, with nothing after it that
// could fail: checked whole before it changes anything (an add at the end of the root tree
// of a unit shape, with fields a table check accepts). The session then skips the copy
// (scenes built in code add primitives by the thousand).
bool appliesInPlace(const SceneDocument& document, const Operation& operation, const Resources& resources);

}  // namespace ray::edit
