// Where a node (edit/node_id.h) is in its scene document, and a walk over every node in
// document order (the outline's order): the one place that knows how the document's tree of
// trees, transblocks, items, inline trees and csg operands is walked for editing.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "edit/node_id.h"
#include "scene/scene_document.h"

namespace ray::edit {

// A node found in a document. Pointers are into the document, valid until it changes.
struct NodePlace {
    NodeId id;
    NamedTree* tree = nullptr;    // the top-level tree holding it (Tree: itself)
    std::vector<Block*> blocks;   // the blocks enclosing it, outermost first (Block: itself last)
    TreeNode* holder = nullptr;   // Block: the tree (top-level or inline) whose block it is
    size_t index = 0;             // Block: its index in holder->blocks; items: in blocks.back()->items; Light: index
    int depth = 0;                // in the outline
    std::string path;             // "root/transblock[1]/object[0]" (DocumentPlace's form); a JSON scene's "groups[1].primitives[0]"
    std::optional<NodeId> parent; // in the outline; none for the camera, globals, lights, trees

    Block& block() const { return *blocks.back(); }  // Block: itself; an item: the block holding it
    SceneItem& item() const { return blocks.back()->items[index]; }
    PrimitiveNode& object() const { return std::get<PrimitiveNode>(item()); }
    MasterReference& placement() const { return std::get<MasterReference>(item()); }
    CsgNode& csg() const { return *std::get<Box<CsgNode>>(item()); }
};

// Calls visit for the camera, the globals, each light, then each top-level tree (the root
// first, then the others in the file's order) and everything in it, in document order: a
// transblock before its items, an inline tree's transblocks and a csg's operands after
// their item. visit returns true to stop.
void walkNodes(SceneDocument& document, const std::function<bool(const NodePlace&)>& visit);

// The node `id`; nullopt when the document has none (removed, or never made).
std::optional<NodePlace> findNode(SceneDocument& document, const NodeId& id);
// The same, or EditError: "there is no object-17 (removed, or never made)".
NodePlace requireNode(SceneDocument& document, const NodeId& id);

// The places of a JSON scene's lights in its file, in the order of SceneDocument::lights, as the
// JSON reader sees them: the place of the group holding the light now, and its index in the
// group's "lights" ("groups[0].lights[1]"; "templateGroups[0].lights[0]" for a template's light,
// one place however many times the template is placed). "" for a light an edit added (a save
// writes it in a group of its own, whose place is known when the file is read again) and for
// every light of an XML scene. One walk at most.
std::vector<std::string> jsonLightPlaces(SceneDocument& document);

}  // namespace ray::edit
