#include "edit/document_patch.h"

#include <cstring>

namespace ray::edit {

namespace {

// A member added to one of these must be compared below (sameItem, sameBlockShell) and
// kept by the header (headerOf, setHeader), or an undo would miss its change: the sizes
// say when one was added (on the platform of CI; another library has other sizes).
#if defined(__GLIBCXX__) && defined(__x86_64__)
static_assert(sizeof(Block) == 280, "a Block member was added: compare it in sameBlockShell");
static_assert(sizeof(PrimitiveNode) == 248, "a PrimitiveNode member was added: compare it in samePrimitive");
static_assert(sizeof(Material) == 216, "a Material member was added: compare it in sameMaterial");
static_assert(sizeof(PrimitiveFiles) == 312 && sizeof(ImageReference) == 80,
              "a PrimitiveFiles or ImageReference member was added: compare it in sameFiles");
static_assert(sizeof(MasterReference) == 56 && sizeof(CsgNode) == 48 && sizeof(TreeNode) == 32,
              "a MasterReference, CsgNode or TreeNode member was added: compare it in sameItem");
static_assert(sizeof(NamedTree) == 96, "a NamedTree member was added: compare it in sameTreeShell");
// SceneDocument::format (XML or JSON) is the file's and no edit changes it: not in the header.
static_assert(sizeof(SceneDocument) == 432, "a SceneDocument member was added: keep it in DocumentPatch::Header");
#endif

// Bit for bit: a value copied unchanged compares equal (a NaN too), a changed one does not.
template <class T>
bool sameBits(const T& a, const T& b) {
    static_assert(std::has_unique_object_representations_v<T> || std::is_floating_point_v<T> ||
                      std::is_same_v<T, Vec3> || std::is_same_v<T, Affine>,
                  "only types without padding are compared bit for bit");
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

bool sameTexture(const TextureMap& a, const TextureMap& b) {
    return a.image == b.image && sameBits(a.repeatU, b.repeatU) && sameBits(a.repeatV, b.repeatV);
}

bool sameMaterial(const Material& a, const Material& b) {
    return sameBits(a.diffuse, b.diffuse) && sameBits(a.ambient, b.ambient) && sameBits(a.specular, b.specular) &&
           sameBits(a.reflective, b.reflective) && sameBits(a.transparent, b.transparent) &&
           sameBits(a.emissive, b.emissive) && sameBits(a.shininess, b.shininess) && sameBits(a.ior, b.ior) &&
           sameBits(a.blend, b.blend) && sameTexture(a.texture, b.texture) && sameTexture(a.bumpMap, b.bumpMap);
}

bool sameImage(const std::optional<ImageReference>& a, const std::optional<ImageReference>& b) {
    if (a.has_value() != b.has_value()) return false;
    return !a || (a->file == b->file && a->line == b->line && a->written == b->written);
}

bool sameFiles(const Box<PrimitiveFiles>& a, const Box<PrimitiveFiles>& b) {
    if (bool(a) != bool(b)) return false;
    if (!a) return true;
    return sameImage(a->texture, b->texture) && sameImage(a->bumpMap, b->bumpMap) &&
           a->missingTexture == b->missingTexture && a->missingBumpMap == b->missingBumpMap &&
           a->meshFile == b->meshFile && a->meshWritten == b->meshWritten;
}

bool samePrimitive(const PrimitiveNode& a, const PrimitiveNode& b) {
    return a.type == b.type && a.line == b.line && a.id == b.id && a.source == b.source && a.mesh == b.mesh &&
           sameMaterial(a.material, b.material) && sameFiles(a.files, b.files);
}

bool sameBlocks(const std::vector<Block>& a, const std::vector<Block>& b);

bool sameTree(const TreeNode& a, const TreeNode& b) { return a.source == b.source && sameBlocks(a.blocks, b.blocks); }

bool sameItem(const SceneItem& a, const SceneItem& b) {
    if (a.index() != b.index()) return false;
    if (const auto* p = std::get_if<PrimitiveNode>(&a)) return samePrimitive(*p, std::get<PrimitiveNode>(b));
    if (const auto* m = std::get_if<MasterReference>(&a)) {
        const MasterReference& n = std::get<MasterReference>(b);
        return m->name == n.name && m->line == n.line && m->source == n.source && m->id == n.id;
    }
    if (const auto* t = std::get_if<Box<TreeNode>>(&a)) return sameTree(**t, *std::get<Box<TreeNode>>(b));
    const CsgNode& c = *std::get<Box<CsgNode>>(a);
    const CsgNode& d = *std::get<Box<CsgNode>>(b);
    if (c.operation != d.operation || c.line != d.line || c.source != d.source || c.id != d.id ||
        c.operands.size() != d.operands.size())
        return false;
    for (size_t i = 0; i < c.operands.size(); ++i)
        if (!sameTree(c.operands[i], d.operands[i])) return false;
    return true;
}

bool sameTransforms(const std::vector<TransformOp>& a, const std::vector<TransformOp>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i].kind != b[i].kind || std::memcmp(a[i].v.data(), b[i].v.data(), sizeof a[i].v) != 0) return false;
    return true;
}

// All of a transblock but its items.
bool sameBlockShell(const Block& a, const Block& b) {
    return a.id == b.id && a.source == b.source && a.bare == b.bare && sameTransforms(a.transforms, b.transforms) &&
           sameBits(a.toParent, b.toParent) && sameBits(a.fromParent, b.fromParent) && sameBits(a.motion, b.motion) &&
           a.items.size() == b.items.size();
}

bool sameBlock(const Block& a, const Block& b) {
    if (!sameBlockShell(a, b)) return false;
    for (size_t i = 0; i < a.items.size(); ++i)
        if (!sameItem(a.items[i], b.items[i])) return false;
    return true;
}

bool sameBlocks(const std::vector<Block>& a, const std::vector<Block>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!sameBlock(a[i], b[i])) return false;
    return true;
}

// The tree's own parts (its blocks aside), which a splice does not change.
bool sameTreeShell(const NamedTree& a, const NamedTree& b) {
    return a.name == b.name && a.id == b.id && a.line == b.line && a.tree.source == b.tree.source;
}

// The first and last elements that differ: {prefix, suffix} of equal ones, not overlapping.
template <class T, class Same>
std::pair<size_t, size_t> commonEnds(const std::vector<T>& a, const std::vector<T>& b, Same same) {
    size_t prefix = 0;
    while (prefix < a.size() && prefix < b.size() && same(a[prefix], b[prefix])) ++prefix;
    size_t suffix = 0;
    while (suffix < a.size() - prefix && suffix < b.size() - prefix &&
           same(a[a.size() - 1 - suffix], b[b.size() - 1 - suffix]))
        ++suffix;
    return {prefix, suffix};
}

class Differ {
public:
    Differ(std::string tree, std::vector<DocumentPatch::Splice>& splices) : tree_(std::move(tree)), splices_(splices) {}

    void blocks(const std::vector<Block>& before, const std::vector<Block>& after) {
        const auto [prefix, suffix] = commonEnds(before, after, sameBlock);
        if (prefix == before.size() && prefix == after.size()) return;
        const size_t removed = before.size() - prefix - suffix, added = after.size() - prefix - suffix;
        if (removed == 1 && added == 1 && sameBlockShell(before[prefix], after[prefix])) {
            route_.push_back(prefix);
            items(before[prefix].items, after[prefix].items);
            route_.pop_back();
            return;
        }
        DocumentPatch::Splice& splice = newSplice(prefix, added);
        splice.blocks.assign(before.begin() + std::ptrdiff_t(prefix), before.begin() + std::ptrdiff_t(prefix + removed));
    }

    void items(const std::vector<SceneItem>& before, const std::vector<SceneItem>& after) {
        const auto [prefix, suffix] = commonEnds(before, after, sameItem);
        if (prefix == before.size() && prefix == after.size()) return;
        const size_t removed = before.size() - prefix - suffix, added = after.size() - prefix - suffix;
        if (removed == 1 && added == 1) {
            const auto* was = std::get_if<Box<TreeNode>>(&before[prefix]);
            const auto* is = std::get_if<Box<TreeNode>>(&after[prefix]);
            if (was && is && (*was)->source == (*is)->source) {
                route_.push_back(prefix);
                blocks((*was)->blocks, (*is)->blocks);
                route_.pop_back();
                return;
            }
        }
        DocumentPatch::Splice& splice = newSplice(prefix, added);
        splice.items.assign(before.begin() + std::ptrdiff_t(prefix), before.begin() + std::ptrdiff_t(prefix + removed));
    }

private:
    DocumentPatch::Splice& newSplice(size_t at, size_t count) {
        DocumentPatch::Splice& splice = splices_.emplace_back();
        splice.tree = tree_;
        splice.route = route_;
        splice.at = at;
        splice.count = count;
        return splice;
    }

    std::string tree_;
    std::vector<DocumentPatch::Splice>& splices_;
    std::vector<size_t> route_;
};

DocumentPatch::Header headerOf(const SceneDocument& d) {
    return {d.file,         d.globals,        d.camera,      d.lights,      d.treeOrder,  d.scenefileLine,
            d.primitiveElements, d.nextObjectId, d.nextBlockId, d.nextNodeId, d.lightIds, d.source,
            d.lightSources, d.jsonSource};
}

void setHeader(SceneDocument& d, DocumentPatch::Header h) {
    d.file = std::move(h.file);
    d.globals = h.globals;
    d.camera = h.camera;
    d.lights = std::move(h.lights);
    d.treeOrder = std::move(h.treeOrder);
    d.scenefileLine = h.scenefileLine;
    d.primitiveElements = h.primitiveElements;
    d.nextObjectId = h.nextObjectId;
    d.nextBlockId = h.nextBlockId;
    d.nextNodeId = h.nextNodeId;
    d.lightIds = std::move(h.lightIds);
    d.source = std::move(h.source);
    d.lightSources = std::move(h.lightSources);
    d.jsonSource = std::move(h.jsonSource);
}

// typedNumbers' entries as `before` has them, where `after` differs.
std::vector<std::pair<std::string, std::optional<std::string>>> numbersBetween(
    const std::map<std::string, std::string>& before, const std::map<std::string, std::string>& after) {
    std::vector<std::pair<std::string, std::optional<std::string>>> entries;
    for (const auto& [key, text] : before) {
        auto now = after.find(key);
        if (now == after.end() || now->second != text) entries.emplace_back(key, text);
    }
    for (const auto& [key, text] : after)
        if (!before.count(key)) entries.emplace_back(key, std::nullopt);
    return entries;
}

// The run of elements the route leads to: a tree's transblocks or a transblock's items.
struct RunPlace {
    std::vector<Block>* blocks = nullptr;
    std::vector<SceneItem>* items = nullptr;
};

RunPlace follow(SceneDocument& document, const DocumentPatch::Splice& splice) {
    TreeNode* tree = &document.trees.at(splice.tree).tree;
    Block* block = nullptr;
    for (size_t i = 0; i < splice.route.size(); ++i) {
        if (i % 2 == 0) block = &tree->blocks.at(splice.route[i]);
        else tree = std::get<Box<TreeNode>>(block->items.at(splice.route[i])).get();
    }
    if (splice.route.size() % 2 == 0) return {&tree->blocks, nullptr};
    return {nullptr, &block->items};
}

// Replaces splice.count elements from splice.at with `with`; returns those replaced.
template <class T>
std::vector<T> replaceRun(std::vector<T>& run, size_t at, size_t count, std::vector<T> with) {
    std::vector<T> replaced(std::make_move_iterator(run.begin() + std::ptrdiff_t(at)),
                            std::make_move_iterator(run.begin() + std::ptrdiff_t(at + count)));
    run.erase(run.begin() + std::ptrdiff_t(at), run.begin() + std::ptrdiff_t(at + count));
    run.insert(run.begin() + std::ptrdiff_t(at), std::make_move_iterator(with.begin()), std::make_move_iterator(with.end()));
    return replaced;
}

size_t stringBytes(const std::string& s) { return s.capacity() > 15 ? s.capacity() + 1 : 0; }
size_t pathBytes(const std::filesystem::path& p) { return stringBytes(p.native()); }

size_t blocksBytes(const std::vector<Block>& blocks);

size_t treeBytes(const TreeNode& tree) { return blocksBytes(tree.blocks); }

size_t itemBytes(const SceneItem& item) {
    if (const auto* p = std::get_if<PrimitiveNode>(&item)) {
        if (!p->files) return 0;
        const PrimitiveFiles& f = *p->files;
        size_t bytes = sizeof(PrimitiveFiles) + stringBytes(f.missingTexture) + stringBytes(f.missingBumpMap) +
                       pathBytes(f.meshFile) + stringBytes(f.meshWritten);
        for (const auto* image : {&f.texture, &f.bumpMap})
            if (*image) bytes += pathBytes((*image)->file) + stringBytes((*image)->written);
        return bytes;
    }
    if (const auto* m = std::get_if<MasterReference>(&item)) return stringBytes(m->name);
    if (const auto* t = std::get_if<Box<TreeNode>>(&item)) return sizeof(TreeNode) + treeBytes(**t);
    const CsgNode& csg = *std::get<Box<CsgNode>>(item);
    size_t bytes = sizeof(CsgNode) + csg.operands.capacity() * sizeof(TreeNode);
    for (const TreeNode& operand : csg.operands) bytes += treeBytes(operand);
    return bytes;
}

size_t itemsBytes(const std::vector<SceneItem>& items) {
    size_t bytes = items.capacity() * sizeof(SceneItem);
    for (const SceneItem& item : items) bytes += itemBytes(item);
    return bytes;
}

size_t blocksBytes(const std::vector<Block>& blocks) {
    size_t bytes = blocks.capacity() * sizeof(Block);
    for (const Block& block : blocks)
        bytes += block.transforms.capacity() * sizeof(TransformOp) + itemsBytes(block.items);
    return bytes;
}

}  // namespace

size_t DocumentPatch::bytes() const {
    size_t total = sizeof(DocumentPatch) + pathBytes(header.file) + header.lights.capacity() * sizeof(Light) +
                   header.lightIds.capacity() * sizeof(int) + header.lightSources.capacity() * sizeof(SourceId) +
                   header.treeOrder.capacity() * sizeof(std::string);
    for (const std::string& name : header.treeOrder) total += stringBytes(name);
    total += numbers.capacity() * sizeof(numbers[0]);
    for (const auto& [key, text] : numbers) total += stringBytes(key) + (text ? stringBytes(*text) : 0);
    total += trees.capacity() * sizeof(TreeSwap);
    for (const TreeSwap& swap : trees)
        if (swap.tree) total += stringBytes(swap.tree->name) + treeBytes(swap.tree->tree);
    total += splices.capacity() * sizeof(Splice);
    for (const Splice& splice : splices)
        total += stringBytes(splice.tree) + splice.route.capacity() * sizeof(size_t) + blocksBytes(splice.blocks) +
                 itemsBytes(splice.items);
    return total;
}

DocumentPatch patchBetween(const SceneDocument& before, const SceneDocument& after, bool settingsOnly) {
    DocumentPatch patch;
    patch.header = headerOf(before);
    patch.numbers = numbersBetween(before.typedNumbers, after.typedNumbers);
    if (settingsOnly) return patch;
    for (const auto& [name, tree] : before.trees) {
        auto now = after.trees.find(name);
        if (now == after.trees.end() || !sameTreeShell(tree, now->second)) patch.trees.push_back({name, tree});
        else Differ(name, patch.splices).blocks(tree.tree.blocks, now->second.tree.blocks);
    }
    for (const auto& [name, tree] : after.trees)
        if (!before.trees.count(name)) patch.trees.push_back({name, std::nullopt});
    return patch;
}

DocumentPatch applyPatch(SceneDocument& document, DocumentPatch patch) {
    DocumentPatch undo;
    undo.header = headerOf(document);
    setHeader(document, std::move(patch.header));
    for (auto& [key, text] : patch.numbers) {
        auto now = document.typedNumbers.find(key);
        undo.numbers.emplace_back(key, now == document.typedNumbers.end() ? std::nullopt
                                                                           : std::optional<std::string>(now->second));
        if (text) document.typedNumbers[key] = std::move(*text);
        else if (now != document.typedNumbers.end()) document.typedNumbers.erase(now);
    }
    for (DocumentPatch::TreeSwap& swap : patch.trees) {
        auto now = document.trees.find(swap.name);
        DocumentPatch::TreeSwap& back = undo.trees.emplace_back();
        back.name = swap.name;
        if (now != document.trees.end()) {
            back.tree = std::move(now->second);
            document.trees.erase(now);
        }
        if (swap.tree) document.trees.emplace(swap.name, std::move(*swap.tree));
    }
    for (DocumentPatch::Splice& splice : patch.splices) {
        const RunPlace run = follow(document, splice);
        DocumentPatch::Splice& back = undo.splices.emplace_back();
        back.tree = splice.tree;
        back.route = splice.route;
        back.at = splice.at;
        if (run.blocks) {
            back.count = splice.blocks.size();
            back.blocks = replaceRun(*run.blocks, splice.at, splice.count, std::move(splice.blocks));
        } else {
            back.count = splice.items.size();
            back.items = replaceRun(*run.items, splice.at, splice.count, std::move(splice.items));
        }
    }
    document.resolveMasters();
    return undo;
}

}  // namespace ray::edit
