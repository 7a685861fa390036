// The scene document (scene_document.h): its copies, its places and paths, its text.
#include "scene/scene_document.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>

#include "core/atomic_file.h"
#include "scene/document_save.h"
#include "scene/canonical_writer.h"
#include "scene/document_splices.h"
#include "scene/json_splices.h"
#include "scene/json_writer.h"
#include "scene/scene_loader.h"
#include "scene/value_text.h"

namespace fs = std::filesystem;

namespace ray {

// ---------------------------------------------------------------------------------------
// Transforms

TransformOp TransformOp::matrix(const Affine& m) {
    TransformOp op;
    op.kind = TransformKind::Matrix;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) op.v[size_t(4 * r + c)] = m.m[r][c];
    return op;
}

std::optional<std::string> TransformOp::whySingular() const {
    switch (kind) {
        case TransformKind::Rotate:
            if (v[0] == 0 && v[1] == 0 && v[2] == 0) return "the rotation axis is zero";
            break;
        case TransformKind::Scale:
            if (v[0] == 0 || v[1] == 0 || v[2] == 0)
                return "a zero scale (a scale of 0 on an axis) flattens what it holds to nothing";
            break;
        case TransformKind::Matrix: {
            for (double number : v)
                if (!std::isfinite(number)) return "the matrix holds a number that is not finite";
            const auto [to, from] = affine();
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c)
                    if (!std::isfinite(to.m[r][c]) || !std::isfinite(from.m[r][c]))
                        return "the matrix is singular (it flattens what it holds)";
            break;
        }
        case TransformKind::Translate: break;
    }
    return std::nullopt;
}

std::pair<Affine, Affine> TransformOp::affine() const {
    const Vec3 xyz{v[0], v[1], v[2]};
    switch (kind) {
        case TransformKind::Translate:
            return {Affine::translation(xyz), Affine::translation(-xyz)};
        case TransformKind::Rotate:
            return {Affine::rotation(xyz, v[3]), Affine::rotation(xyz, -v[3])};
        case TransformKind::Scale:
            return {Affine::scaling(xyz), Affine::scaling({1 / xyz.x, 1 / xyz.y, 1 / xyz.z})};
        case TransformKind::Matrix:
            break;
    }
    Affine m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) m.m[r][c] = v[size_t(4 * r + c)];
    return {m, m.inverse()};
}

// M = T1 · T2 · … · Tn: the last transform listed acts on the objects first.
void composeBlock(Block& block) {
    block.toParent = Affine::identity();
    block.fromParent = Affine::identity();
    for (const TransformOp& op : block.transforms) {
        auto [to, from] = op.affine();
        block.toParent = block.toParent * to;
        block.fromParent = from * block.fromParent;
    }
}

// ---------------------------------------------------------------------------------------
// The document

SceneDocument::SceneDocument(const SceneDocument& other)
    : file(other.file), format(other.format), globals(other.globals), camera(other.camera), lights(other.lights), trees(other.trees),
      treeOrder(other.treeOrder), scenefileLine(other.scenefileLine), primitiveElements(other.primitiveElements),
      nextObjectId(other.nextObjectId), nextBlockId(other.nextBlockId), nextNodeId(other.nextNodeId),
      lightIds(other.lightIds), source(other.source),
      lightSources(other.lightSources), typedNumbers(other.typedNumbers), jsonSource(other.jsonSource) {
    resolveMasters();  // the copied references point into `other`
}

SceneDocument& SceneDocument::operator=(const SceneDocument& other) {
    if (this != &other) *this = SceneDocument(other);
    return *this;
}

namespace {

template <class Visit>
void forEachMaster(TreeNode& node, Visit& visit) {
    for (Block& block : node.blocks)
        for (SceneItem& item : block.items) {
            if (auto* master = std::get_if<MasterReference>(&item)) visit(*master);
            else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) forEachMaster(**subtree, visit);
            else if (auto* csg = std::get_if<Box<CsgNode>>(&item))
                for (TreeNode& operand : (*csg)->operands) forEachMaster(operand, visit);
        }
}

}  // namespace

void SceneDocument::resolveMasters() {
    auto resolve = [this](MasterReference& master) {
        auto it = trees.find(master.name);
        master.target = it == trees.end() ? nullptr : &it->second;
    };
    for (auto& [name, tree] : trees) forEachMaster(tree.tree, resolve);
}

NamedTree& SceneDocument::rootToSet() {
    auto [it, added] = trees.try_emplace("root");
    if (added) {
        it->second.name = "root";
        it->second.id = nextNodeId++;
        treeOrder.push_back("root");
    }
    return it->second;
}

namespace {

void assignIds(TreeNode& node, int& next) {
    for (Block& block : node.blocks)
        for (SceneItem& item : block.items) {
            if (auto* master = std::get_if<MasterReference>(&item)) {
                if (master->id < 0) master->id = next++;
            } else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
                assignIds(**subtree, next);
            } else if (auto* csg = std::get_if<Box<CsgNode>>(&item)) {
                if ((*csg)->id < 0) (*csg)->id = next++;
                for (TreeNode& operand : (*csg)->operands) assignIds(operand, next);
            }
        }
}

}  // namespace

void assignNodeIds(SceneDocument& document) {
    for (NamedTree* tree : treesInOrder(document)) {
        if (tree->id < 0) tree->id = document.nextNodeId++;
        assignIds(tree->tree, document.nextNodeId);
    }
    while (document.lightIds.size() < document.lights.size()) document.lightIds.push_back(document.nextNodeId++);
    document.lightIds.resize(document.lights.size());
}

// ---------------------------------------------------------------------------------------
// Places

std::vector<NamedTree*> treesInOrder(SceneDocument& document) {
    std::vector<NamedTree*> trees;
    std::set<std::string> listed;
    for (const std::string& name : document.treeOrder) {
        auto it = document.trees.find(name);
        if (it != document.trees.end() && listed.insert(name).second) trees.push_back(&it->second);
    }
    for (auto& [name, tree] : document.trees)
        if (!listed.count(name)) trees.push_back(&tree);
    return trees;
}

namespace {

// Walks a document in its order, with the place of every block and object.
class Walker {
public:
    std::function<bool(Block&, const DocumentPlace&)> onBlock;  // true: stop
    std::function<bool(PrimitiveNode&, const DocumentPlace&)> onObject;

    void walk(SceneDocument& document) {
        for (NamedTree* tree : ray::treesInOrder(document)) {
            place_.tree = tree;
            place_.blocks.clear();
            if (walk(tree->tree, tree->name)) return;
        }
    }

private:
    bool walk(TreeNode& node, const std::string& prefix) {
        for (size_t b = 0; b < node.blocks.size(); ++b) {
            Block& block = node.blocks[b];
            const std::string blockPath = prefix + "/transblock[" + std::to_string(b) + "]";
            place_.blocks.push_back(&block);
            place_.block = &block;
            place_.item = 0;
            place_.path = blockPath;
            if (onBlock && onBlock(block, place_)) return true;
            for (size_t i = 0; i < block.items.size(); ++i) {
                SceneItem& item = block.items[i];
                const std::string itemPath = blockPath + "/object[" + std::to_string(i) + "]";
                if (auto* primitive = std::get_if<PrimitiveNode>(&item)) {
                    if (onObject) {
                        place_.block = &block;
                        place_.item = i;
                        place_.path = itemPath;
                        if (onObject(*primitive, place_)) return true;
                    }
                } else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
                    if (walk(**subtree, itemPath)) return true;
                } else if (auto* csg = std::get_if<Box<CsgNode>>(&item)) {
                    for (size_t k = 0; k < (*csg)->operands.size(); ++k)
                        if (walk((*csg)->operands[k], itemPath + "/operand[" + std::to_string(k) + "]")) return true;
                }
            }
            place_.blocks.pop_back();
        }
        return false;
    }

    DocumentPlace place_;
};

}  // namespace

std::optional<DocumentPlace> findObject(SceneDocument& document, int id) {
    std::optional<DocumentPlace> found;
    Walker walker;
    walker.onObject = [&](PrimitiveNode& node, const DocumentPlace& place) {
        if (node.id == id) found = place;
        return found.has_value();
    };
    walker.walk(document);
    return found;
}

std::optional<DocumentPlace> findBlock(SceneDocument& document, int id) {
    std::optional<DocumentPlace> found;
    Walker walker;
    walker.onBlock = [&](Block& block, const DocumentPlace& place) {
        if (block.id == id) found = place;
        return found.has_value();
    };
    walker.walk(document);
    return found;
}

void forEachObject(SceneDocument& document, const std::function<void(PrimitiveNode&, const DocumentPlace&)>& visit) {
    Walker walker;
    walker.onObject = [&](PrimitiveNode& node, const DocumentPlace& place) {
        visit(node, place);
        return false;
    };
    walker.walk(document);
}

void forEachBlock(SceneDocument& document, const std::function<void(Block&, const DocumentPlace&)>& visit) {
    Walker walker;
    walker.onBlock = [&](Block& block, const DocumentPlace& place) {
        visit(block, place);
        return false;
    };
    walker.walk(document);
}

std::pair<Affine, Affine> composedPlacement(const std::vector<Block*>& blocks) {
    Affine to = Affine::identity(), from = Affine::identity();
    for (const Block* block : blocks) {  // as the flattener composes, outermost first
        to = to * block->toParent;
        from = block->fromParent * from;
    }
    return {to, from};
}

// ---------------------------------------------------------------------------------------
// Numbers as typed

std::string numberKey(const std::string& owner, const std::string& field, size_t index) {
    return owner + " " + field + " " + std::to_string(index);
}

std::string typedNumberText(const SceneDocument& document, const std::string& key, double value) {
    auto typed = document.typedNumbers.find(key);
    if (typed != document.typedNumbers.end()) {
        const NumberReading read = readNumber(typed->second.c_str());
        if (read.kind == NumberReading::Kind::Number && std::memcmp(&read.value, &value, sizeof value) == 0)
            return typed->second;
    }
    return shortestNumber(value);
}

void setTypedNumber(SceneDocument& document, const std::string& key, const std::string& text) {
    if (readNumber(text.c_str()).kind != NumberReading::Kind::Number)
        throw InputError("error: '" + text + "' is not a finite number");
    document.typedNumbers[key] = text;
}

// ---------------------------------------------------------------------------------------
// Lights

size_t addLight(SceneDocument& document, const Light& light) {
    document.lightSources.resize(document.lights.size(), kNoSource);  // those added in code have none
    assignNodeIds(document);
    document.lights.push_back(light);
    document.lightSources.push_back(kNoSource);
    document.lightIds.push_back(document.nextNodeId++);
    return document.lights.size() - 1;
}

void removeLight(SceneDocument& document, size_t index) {
    if (index >= document.lights.size())
        throw InputError("error: light " + std::to_string(index) + " does not exist (the scene has " +
                         std::to_string(document.lights.size()) + ")");
    document.lights.erase(document.lights.begin() + std::ptrdiff_t(index));
    if (index < document.lightSources.size())
        document.lightSources.erase(document.lightSources.begin() + std::ptrdiff_t(index));
    if (index < document.lightIds.size()) document.lightIds.erase(document.lightIds.begin() + std::ptrdiff_t(index));
}

// ---------------------------------------------------------------------------------------
// Text

namespace {

// The format a save to `target` writes: the one its name says (.json, .xml, in any case),
// else the document's own.
SceneFormat savedFormat(const SceneDocument& document, const fs::path& target) {
    const std::string extension = target.extension().string();
    if (sameName(extension.c_str(), ".json")) return SceneFormat::Json;
    if (sameName(extension.c_str(), ".xml")) return SceneFormat::Xml;
    return document.format;
}

// Whether the save is the document's own text with splices: saved in the format it was read in.
bool keepsSourceText(const SceneDocument& document, const fs::path& target) {
    return document.source && savedFormat(document, target) == document.format;
}

}  // namespace

std::string documentToText(const SceneDocument& document, const Resources& resources, const fs::path& target) {
    if (savedFormat(document, target) == SceneFormat::Json) {
        if (document.jsonSource)  // the JSON it was read from, with its edits (json_splices.h)
            return applySplices(document.jsonSource->text, jsonDocumentSplices(document, resources, target));
        return documentToJson(document, resources, target);  // a scene made in code, or an XML one converted
    }
    if (keepsSourceText(document, target)) {
        const std::vector<Splice> splices = documentSplices(document, resources, target);
        return applySplices(document.source->bytes(), splices);
    }
    return CanonicalWriter(document, resources, target).document();
}

std::string documentFileBytes(const SceneDocument& document, const Resources& resources, const fs::path& target) {
    std::string text = documentToText(document, resources, target);
    return keepsSourceText(document, target) ? document.source->fileBytes(text) : text;
}

namespace {

// The names of the document's trees (sorted: a std::map's keys).
std::vector<std::string> treeNames(const SceneDocument& document) {
    std::vector<std::string> names;
    for (const auto& [name, tree] : document.trees) names.push_back(name);
    return names;
}

// The primitive elements in `node`, inline trees and csg operands included.
size_t objectCount(const TreeNode& node) {
    size_t count = 0;
    for (const Block& block : node.blocks)
        for (const SceneItem& item : block.items) {
            if (std::holds_alternative<PrimitiveNode>(item)) ++count;
            else if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) count += objectCount(**subtree);
            else if (const auto* csg = std::get_if<Box<CsgNode>>(&item))
                for (const TreeNode& operand : (*csg)->operands) count += objectCount(operand);
        }
    return count;
}

size_t objectCount(const SceneDocument& document) {
    size_t count = 0;
    for (const auto& [name, tree] : document.trees) count += objectCount(tree.tree);
    return count;
}

// What of `saved` its text, read back as `reread`, says otherwise (the trees' names, the
// number of objects and lights); nullopt when it says the same.
std::optional<std::string> readsOtherwise(const SceneDocument& saved, const SceneDocument& reread) {
    std::vector<std::string> names = treeNames(saved);
    if (reread.format == SceneFormat::Json && !saved.trees.count("root"))  // JSON's "groups" are the tree "root"
        names.insert(std::lower_bound(names.begin(), names.end(), "root"), "root");
    if (names != treeNames(reread)) return std::string("its trees' names read back otherwise");
    if (objectCount(saved) != objectCount(reread))
        return "it reads back as " + std::to_string(objectCount(reread)) + " objects, not " +
               std::to_string(objectCount(saved));
    if (saved.lights.size() != reread.lights.size())
        return "it reads back as " + std::to_string(reread.lights.size()) + " lights, not " +
               std::to_string(saved.lights.size());
    return std::nullopt;
}

// `bytes`, about to be written to `target`, read as a fresh load of `target` would read
// them (pass 1 of the loader, every rule of the format checked; files named are resolved
// but not read). Throws InputError, with the reason, when they would not load, or load as
// another scene.
void checkLoadsBack(const SceneDocument& document, const std::string& bytes, const fs::path& target) {
    LoadOptions quiet;
    quiet.loadImages = false;
    quiet.warn = [](const std::string&) {};  // a texture not found reads with a warning: the loader's concern
    const std::string refused = "error: the scene is not saved, " + target.string() + " is kept as it was: ";
    SceneDocument reread;
    try {
        reread = loadSceneDocumentFromText(bytes, target, quiet);
    } catch (const InputError& e) {
        throw InputError(refused + "the text to be written would not load: " + e.what());
    }
    if (std::optional<std::string> why = readsOtherwise(document, reread))
        throw InputError(refused + "the text to be written would not load as this scene: " + *why);
}

}  // namespace

void saveDocument(const SceneDocument& document, const Resources& resources, const fs::path& target) {
    saveDocument(document, resources, target, WriteOptions{});
}

void saveDocument(const SceneDocument& document, const Resources& resources, const fs::path& target,
                  const WriteOptions& options) {
    const std::string bytes = documentFileBytes(document, resources, target);
    checkLoadsBack(document, bytes, target);
    writeFileAtomically(target, bytes, options);
}

}  // namespace ray
