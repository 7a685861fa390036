// Edits of the document's structure (document_edits.h).
#include "scene/document_edits.h"

#include <algorithm>
#include <cmath>
#include <functional>


namespace fs = std::filesystem;

namespace ray {
namespace {

[[noreturn]] void refuse(const std::string& why) { throw InputError("error: " + why); }

DocumentPlace placeOf(SceneDocument& document, int id) {
    std::optional<DocumentPlace> place = findObject(document, id);
    if (!place) refuse("object " + std::to_string(id) + " does not exist (removed, or never made)");
    return *place;
}

PrimitiveNode& objectAt(const DocumentPlace& place) { return std::get<PrimitiveNode>(place.block->items[place.item]); }

// A copy with no element of the file's text and new ids: written afresh where it goes.
PrimitiveNode fresh(const PrimitiveNode& original, SceneDocument& document) {
    PrimitiveNode copy = original;
    copy.id = document.nextObjectId++;
    copy.source = kNoSource;
    copy.line = 0;
    ++document.primitiveElements;
    return copy;
}

}  // namespace

int addPrimitive(SceneDocument& document, PrimitiveType type, const Material& material,
                 const std::vector<TransformOp>& transforms) {
    if (type == PrimitiveType::Mesh || type == PrimitiveType::Csg)
        refuse(std::string("a ") + primitiveTypeName(type) + " cannot be added here; add a cube, sphere, cylinder, "
                                                             "cone or torus");
    for (const TransformOp& op : transforms)
        if (auto why = op.whySingular()) refuse("the new object's transform: " + *why);
    PrimitiveNode node;
    node.type = type;
    node.material = material;
    node.id = document.nextObjectId++;
    ++document.primitiveElements;
    Block block;
    block.id = document.nextBlockId++;
    block.transforms = transforms;
    composeBlock(block);
    block.items.push_back(std::move(node));
    document.rootToSet().tree.blocks.push_back(std::move(block));
    return document.nextObjectId - 1;
}

void removeObject(SceneDocument& document, int id) {
    const DocumentPlace place = placeOf(document, id);
    place.block->items.erase(place.block->items.begin() + std::ptrdiff_t(place.item));
}

int duplicateObject(SceneDocument& document, int id) {
    const DocumentPlace place = placeOf(document, id);
    PrimitiveNode copy = fresh(objectAt(place), document);
    const int copyId = copy.id;
    place.block->items.insert(place.block->items.begin() + std::ptrdiff_t(place.item + 1), std::move(copy));
    return copyId;
}

int groupIntoTransblock(SceneDocument& document, const std::vector<int>& ids) {
    if (ids.empty()) refuse("a group needs at least one object");
    std::vector<size_t> items;
    Block* block = nullptr;
    for (int id : ids) {
        const DocumentPlace place = placeOf(document, id);
        if (block && place.block != block)
            refuse("objects " + std::to_string(ids.front()) + " and " + std::to_string(id) +
                   " are in different transblocks; group objects of one transblock");
        block = place.block;
        if (std::find(items.begin(), items.end(), place.item) != items.end())
            refuse("object " + std::to_string(id) + " is named twice");
        items.push_back(place.item);
    }
    std::sort(items.begin(), items.end());
    Block group;
    group.id = document.nextBlockId++;
    for (size_t item : items) group.items.push_back(std::move(block->items[item]));
    composeBlock(group);
    TreeNode tree;
    tree.blocks.push_back(std::move(group));
    block->items[items.front()] = Box<TreeNode>(std::move(tree));
    for (size_t k = items.size(); k-- > 1;) block->items.erase(block->items.begin() + std::ptrdiff_t(items[k]));
    return document.nextBlockId - 1;
}

void renameTree(SceneDocument& document, const std::string& from, const std::string& to) {
    if (to.empty()) refuse("a tree's name must not be empty");
    if (from == "root" || to == "root") refuse("the tree named root is the scene; it keeps its name");
    auto it = document.trees.find(from);
    if (it == document.trees.end()) refuse("there is no tree named '" + from + "'");
    if (document.trees.count(to)) refuse("a tree is named '" + to + "' already");
    NamedTree tree = std::move(it->second);
    document.trees.erase(it);
    tree.name = to;
    document.trees.emplace(to, std::move(tree));
    std::replace(document.treeOrder.begin(), document.treeOrder.end(), from, to);
    // Every master placing it, wherever it is.
    std::function<void(TreeNode&)> rename = [&](TreeNode& node) {
        for (Block& block : node.blocks)
            for (SceneItem& item : block.items) {
                if (auto* master = std::get_if<MasterReference>(&item)) {
                    if (master->name == from) master->name = to;
                } else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
                    rename(**subtree);
                } else if (auto* csg = std::get_if<Box<CsgNode>>(&item)) {
                    for (TreeNode& operand : (*csg)->operands) rename(operand);
                }
            }
    };
    for (auto& [name, named] : document.trees) rename(named.tree);
    document.resolveMasters();
}

void setTexture(SceneDocument& document, int id, const fs::path& file, double repeatU, double repeatV) {
    if (!(repeatU > 0) || !(repeatV > 0) || !std::isfinite(repeatU) || !std::isfinite(repeatV))
        refuse("a texture's repeats must be positive finite numbers");
    const fs::path resolved = file.is_absolute() ? file : document.file.parent_path() / file;
    std::error_code ec;
    if (!fs::is_regular_file(resolved, ec)) refuse("texture file " + resolved.string() + " is not a file");
    PrimitiveNode& node = objectAt(placeOf(document, id));
    PrimitiveFiles& files = node.filesToSet();
    files.texture = ImageReference{resolved, 0, ""};
    files.missingTexture.clear();
    node.material.texture = {-1, repeatU, repeatV};
}

}  // namespace ray
