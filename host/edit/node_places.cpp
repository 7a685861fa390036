#include "edit/node_places.h"

#include <charconv>
#include <map>
#include <utility>

#include "edit/edit_error.h"
#include "scene/json_splices.h"

namespace ray::edit {

namespace {

class NodeWalk {
public:
    NodeWalk(SceneDocument& document, const std::function<bool(const NodePlace&)>& visit)
        : document_(document), visit_(visit), json_(document.format == SceneFormat::Json) {}

    void run() {
        if (emit({NodeKind::Camera, 0}, 0, std::nullopt) || emit({NodeKind::Globals, 0}, 0, std::nullopt)) return;
        for (size_t i = 0; i < document_.lights.size(); ++i) {
            place_.index = i;
            if (emit({NodeKind::Light, i < document_.lightIds.size() ? document_.lightIds[i] : -1}, 0, std::nullopt))
                return;
        }
        size_t templates = 0;  // a JSON scene's trees but "root" are its templateGroups, in order
        for (NamedTree* tree : treesInOrder(document_)) {
            place_ = {};
            place_.tree = tree;
            place_.path = tree->name;
            templateGroup_ = json_ && tree->name != "root";
            if (json_) place_.path = templateGroup_ ? "templateGroups[" + std::to_string(templates++) + "]" : "";
            const NodeId treeId{NodeKind::Tree, tree->id};
            if (emit(treeId, 0, std::nullopt) || walkTree(tree->tree, 1, treeId)) return;
        }
    }

private:
    bool emit(const NodeId& id, int depth, const std::optional<NodeId>& parent) {
        place_.id = id;
        place_.depth = depth;
        place_.parent = parent;
        return visit_(place_);
    }

    // place_.path is one buffer, each level's part appended and cut off again: a walk is made
    // for every lookup of a node (findNode), and a new string for every node of a scene of
    // 10^4 objects made each add of one cost more than the add itself.
    // `first`: a JSON place's number of the first block (the groups of a group's inline
    // trees are one "groups" array).
    bool walkTree(TreeNode& node, int depth, const NodeId& parent, size_t first = 0) {
        const size_t prefix = place_.path.size();
        const bool templateGroup = std::exchange(templateGroup_, false);
        for (size_t b = 0; b < node.blocks.size(); ++b) {
            Block& block = node.blocks[b];
            if (!json_) appendPath("/transblock[", b);
            else if (!templateGroup || b > 0) appendPath(prefix ? ".groups[" : "groups[", first + b);
            place_.blocks.push_back(&block);
            place_.holder = &node;
            place_.index = b;
            const NodeId blockId{NodeKind::Block, block.id};
            if (emit(blockId, depth, parent) || walkItems(block, depth + 1, blockId)) return true;
            place_.blocks.pop_back();
            place_.path.resize(prefix);
        }
        return false;
    }

    bool walkItems(Block& block, int depth, const NodeId& parent) {
        const size_t blockPath = place_.path.size();
        size_t primitives = 0, groups = 0;  // a JSON group's of each
        for (size_t i = 0; i < block.items.size(); ++i) {
            SceneItem& item = block.items[i];
            place_.path.resize(blockPath);
            if (!json_) appendPath("/object[", i);
            else if (std::holds_alternative<PrimitiveNode>(item)) appendPath(".primitives[", primitives++);
            auto at = [&] {
                place_.holder = nullptr;
                place_.index = i;
            };
            if (auto* primitive = std::get_if<PrimitiveNode>(&item)) {
                at();
                if (emit({NodeKind::Object, primitive->id}, depth, parent)) return true;
            } else if (auto* master = std::get_if<MasterReference>(&item)) {
                at();
                if (emit({NodeKind::Placement, master->id}, depth, parent)) return true;
            } else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
                // An inline tree is no node of its own: its transblocks are the block's children.
                if (walkTree(**subtree, depth, parent, groups)) return true;
                groups += (*subtree)->blocks.size();
            } else if (auto* csg = std::get_if<Box<CsgNode>>(&item)) {
                at();
                const NodeId csgId{NodeKind::Csg, (*csg)->id};
                if (emit(csgId, depth, parent)) return true;
                const size_t itemPath = place_.path.size();
                for (size_t k = 0; k < (*csg)->operands.size(); ++k) {
                    place_.path.resize(itemPath);
                    appendPath("/operand[", k);
                    if (walkTree((*csg)->operands[k], depth + 1, csgId)) return true;
                }
            }
        }
        place_.path.resize(blockPath);
        return false;
    }

    void appendPath(const char* part, size_t index) {
        char number[24];
        char* end = std::to_chars(number, number + sizeof number, index).ptr;
        place_.path.append(part).append(number, end).push_back(']');
    }

    SceneDocument& document_;
    const std::function<bool(const NodePlace&)>& visit_;
    NodePlace place_;
    // A JSON scene's places are its file's: "groups[2].primitives[0]", "templateGroups[0]".
    const bool json_;
    bool templateGroup_ = false;  // the tree walked next is a template: its first block is its group
};

}  // namespace

void walkNodes(SceneDocument& document, const std::function<bool(const NodePlace&)>& visit) {
    NodeWalk(document, visit).run();
}

std::optional<NodePlace> findNode(SceneDocument& document, const NodeId& id) {
    std::optional<NodePlace> found;
    walkNodes(document, [&](const NodePlace& place) {
        if (place.id == id) found = place;
        return found.has_value();
    });
    return found;
}

NodePlace requireNode(SceneDocument& document, const NodeId& id) {
    std::optional<NodePlace> place = findNode(document, id);
    if (!place) throw EditError(id.text() + " does not exist (removed, or never made)", EditError::Kind::Value, "",
                                id.text());
    return *place;
}

std::vector<std::string> jsonLightPlaces(SceneDocument& document) {
    std::vector<std::string> places(document.lights.size());
    if (document.format != SceneFormat::Json || !document.jsonSource) return places;
    const JsonSource& source = *document.jsonSource;
    // A light is a value in its group's "lights" array: the lights by the group's value, each
    // with its text ".lights[K]".
    std::map<SourceId, std::vector<std::pair<size_t, std::string>>> byGroup;
    for (size_t i = 0; i < places.size() && i < document.lightSources.size(); ++i) {
        const SourceId light = document.lightSources[i];
        if (light == kNoSource || light >= source.tree.valueCount()) continue;
        const JsonValue lights = source.tree.at(source.parents[light]);
        if (!lights.isArray()) continue;
        size_t k = 0;
        for (JsonValue value = lights.first(); value && value.index() != light; value = value.next()) ++k;
        byGroup[source.parents[lights.index()]].emplace_back(i, ".lights[" + std::to_string(k) + "]");
    }
    if (byGroup.empty()) return places;
    walkNodes(document, [&](const NodePlace& place) {
        if (place.id.kind != NodeKind::Block) return false;
        auto group = byGroup.find(place.block().source);
        if (group == byGroup.end()) return false;
        for (const auto& [light, inGroup] : group->second) places[light] = place.path + inGroup;
        byGroup.erase(group);  // a group duplicated by an edit keeps its value: its first place
        return byGroup.empty();
    });
    return places;
}

}  // namespace ray::edit
