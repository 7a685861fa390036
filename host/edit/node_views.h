// What an editor shows of a scene document: its outline (every node in document order, with
// its parent and depth) and one node's description with its fields' values. The viewer
// answers GET /outline and GET /node with these (edit_json.h), the C++ API and Python give
// them as structs.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "edit/field_table.h"
#include "edit/node_id.h"
#include "scene/scene.h"
#include "scene/scene_document.h"

namespace ray::edit {

struct OutlineEntry {
    NodeId id;
    std::optional<NodeId> parent;  // none for the camera, the globals, lights and trees
    int depth = 0;
    // What kind of node it is in the words of its file's format: an XML scene's are the kinds'
    // names (nodeKindName: "transblock", "tree", "placement"); a JSON scene's are SPEC §7's:
    // "group", "template group" (a tree but the root, which is the file's "groups"), "template
    // use" (a placement: a group naming a template).
    std::string label;
    std::string text;   // what it is, for a person: "sphere", "point light", "master leg" (JSON: the template's name)
    // Its place in the file's tree: "root/transblock[1]/object[0]"; a JSON scene's as its reader
    // names it, "groups[1].primitives[0]", "groups[0].lights[0]" (jsonLightPlaces). "" for the
    // camera and the globals, an XML scene's lights, and a JSON light an edit added.
    std::string path;
    std::string shape;  // an object's: "sphere"
    std::string type;   // a light's: "point"
    std::string name;   // a tree's
    std::optional<NodeId> master;  // a placement's: the tree it places (none: no tree has its name)
};

std::vector<OutlineEntry> outline(SceneDocument& document);

struct NodeView {
    OutlineEntry entry;
    int line = 0;      // in the file it was read from; 0 when made by an edit
    // Its fields that apply, in the table's order, with their values.
    std::vector<std::pair<const EditField*, FieldValue>> fields;
    // An object's.
    size_t instances = 0;              // how many times it is rendered
    std::optional<NodeId> inMaster;    // the master tree it is in; none in the root
    bool ownBlock = false;             // alone in its transblock (its transforms are its own)
};

// Throws EditError for a node that does not exist.
NodeView describeNode(SceneDocument& document, const Scene& scene, const NodeId& id);

}  // namespace ray::edit
