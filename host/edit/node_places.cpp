#include "edit/node_places.h"

#include "edit/edit_error.h"

namespace ray::edit {

namespace {

class NodeWalk {
public:
    NodeWalk(SceneDocument& document, const std::function<bool(const NodePlace&)>& visit)
        : document_(document), visit_(visit) {}

    void run() {
        if (emit({NodeKind::Camera, 0}, 0, std::nullopt) || emit({NodeKind::Globals, 0}, 0, std::nullopt)) return;
        for (size_t i = 0; i < document_.lights.size(); ++i) {
            place_.index = i;
            if (emit({NodeKind::Light, i < document_.lightIds.size() ? document_.lightIds[i] : -1}, 0, std::nullopt))
                return;
        }
        for (NamedTree* tree : treesInOrder(document_)) {
            place_ = {};
            place_.tree = tree;
            place_.path = tree->name;
            const NodeId treeId{NodeKind::Tree, tree->id};
            if (emit(treeId, 0, std::nullopt) || walkTree(tree->tree, tree->name, 1, treeId)) return;
        }
    }

private:
    bool emit(const NodeId& id, int depth, const std::optional<NodeId>& parent) {
        place_.id = id;
        place_.depth = depth;
        place_.parent = parent;
        return visit_(place_);
    }

    bool walkTree(TreeNode& node, const std::string& prefix, int depth, const NodeId& parent) {
        for (size_t b = 0; b < node.blocks.size(); ++b) {
            Block& block = node.blocks[b];
            const std::string blockPath = prefix + "/transblock[" + std::to_string(b) + "]";
            place_.blocks.push_back(&block);
            place_.holder = &node;
            place_.index = b;
            place_.path = blockPath;
            const NodeId blockId{NodeKind::Block, block.id};
            if (emit(blockId, depth, parent) || walkItems(block, blockPath, depth + 1, blockId)) return true;
            place_.blocks.pop_back();
        }
        return false;
    }

    bool walkItems(Block& block, const std::string& blockPath, int depth, const NodeId& parent) {
        for (size_t i = 0; i < block.items.size(); ++i) {
            SceneItem& item = block.items[i];
            const std::string itemPath = blockPath + "/object[" + std::to_string(i) + "]";
            auto at = [&] {
                place_.holder = nullptr;
                place_.index = i;
                place_.path = itemPath;
            };
            if (auto* primitive = std::get_if<PrimitiveNode>(&item)) {
                at();
                if (emit({NodeKind::Object, primitive->id}, depth, parent)) return true;
            } else if (auto* master = std::get_if<MasterReference>(&item)) {
                at();
                if (emit({NodeKind::Placement, master->id}, depth, parent)) return true;
            } else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
                // An inline tree is no node of its own: its transblocks are the block's children.
                if (walkTree(**subtree, itemPath, depth, parent)) return true;
            } else if (auto* csg = std::get_if<Box<CsgNode>>(&item)) {
                at();
                const NodeId csgId{NodeKind::Csg, (*csg)->id};
                if (emit(csgId, depth, parent)) return true;
                for (size_t k = 0; k < (*csg)->operands.size(); ++k)
                    if (walkTree((*csg)->operands[k], itemPath + "/operand[" + std::to_string(k) + "]", depth + 1,
                                 csgId))
                        return true;
            }
        }
        return false;
    }

    SceneDocument& document_;
    const std::function<bool(const NodePlace&)>& visit_;
    NodePlace place_;
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

}  // namespace ray::edit
