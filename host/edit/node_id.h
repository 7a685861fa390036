// The names of what an editor can select in a scene document (a node): the camera, the
// globals, a light, a top-level tree, a transblock, an object, a placement of a master, a
// csg object. Each has a stable id in its document (scene/scene_document.h); a node's name
// is its kind and that id, written "object-12" (docs/modeler-protocol.md), the same for the
// page, the C++ API and Python.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace ray::edit {

enum class NodeKind { Camera, Globals, Light, Tree, Block, Object, Placement, Csg };

struct NodeId {
    NodeKind kind = NodeKind::Camera;
    int number = 0;  // the document's id of it; 0 for the camera and the globals

    // "camera", "globals", "light-3", "tree-0", "block-7", "object-12", "placement-2", "csg-1".
    std::string text() const;
    // The id `text` names; nullopt when it names none (the wrong form, a number out of range).
    static std::optional<NodeId> parse(std::string_view text);

    bool operator==(const NodeId&) const = default;
};

// The kind as the protocol and the outline name it: "camera", "globals", "light", "tree",
// "transblock", "object", "placement", "csg".
const char* nodeKindName(NodeKind kind);

}  // namespace ray::edit
