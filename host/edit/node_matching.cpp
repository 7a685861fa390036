#include "edit/node_matching.h"

#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <string_view>
#include <vector>

#include "core/fnv1a.h"

namespace ray::edit {

namespace {

// A 64-bit FNV-1a hash of an element's content: what it holds and says, not where it is
// (no ids, lines or places in the text).
class ContentHash {
public:
    template <class T>
    void value(const T& v) {
        static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
        bytes(&v, sizeof v);
    }
    void vec(const Vec3& v) {
        value(v.x);
        value(v.y);
        value(v.z);
    }
    void text(std::string_view s) {
        value(s.size());
        bytes(s.data(), s.size());
    }
    uint64_t result() const { return hash_.value(); }

private:
    void bytes(const void* data, size_t size) { hash_.add(data, size); }
    Fnv1a hash_;
};

uint64_t blockKey(const Block& block);

uint64_t treeKey(const TreeNode& tree) {
    ContentHash h;
    h.value(tree.blocks.size());
    for (const Block& block : tree.blocks) h.value(blockKey(block));
    return h.result();
}

void hashTexture(ContentHash& h, const TextureMap& map) {
    h.value(map.image);
    h.value(map.repeatU);
    h.value(map.repeatV);
}

void hashPrimitive(ContentHash& h, const PrimitiveNode& p) {
    h.value(p.type);
    const Material& m = p.material;
    for (const Vec3* v : {&m.diffuse, &m.ambient, &m.specular, &m.reflective, &m.transparent, &m.emissive}) h.vec(*v);
    h.value(m.shininess);
    h.value(m.ior);
    h.value(m.blend);
    hashTexture(h, m.texture);
    hashTexture(h, m.bumpMap);
    h.value(p.mesh);
    if (!p.files) return;
    const PrimitiveFiles& f = *p.files;
    for (const auto* image : {&f.texture, &f.bumpMap}) h.text(*image ? (*image)->file.native() : std::string());
    h.text(f.missingTexture);
    h.text(f.missingBumpMap);
    h.text(f.meshFile.native());
}

uint64_t itemKey(const SceneItem& item) {
    ContentHash h;
    h.value(item.index());
    if (const auto* p = std::get_if<PrimitiveNode>(&item)) hashPrimitive(h, *p);
    else if (const auto* m = std::get_if<MasterReference>(&item)) h.text(m->name);
    else if (const auto* t = std::get_if<Box<TreeNode>>(&item)) h.value(treeKey(**t));
    else {
        const CsgNode& csg = *std::get<Box<CsgNode>>(item);
        h.value(csg.operation);
        for (const TreeNode& operand : csg.operands) h.value(treeKey(operand));
    }
    return h.result();
}

uint64_t blockKey(const Block& block) {
    ContentHash h;
    h.value(block.bare);
    h.value(block.transforms.size());
    for (const TransformOp& op : block.transforms) {
        h.value(op.kind);
        for (double v : op.v) h.value(v);
    }
    h.vec(block.motion);
    h.value(block.items.size());
    for (const SceneItem& item : block.items) h.value(itemKey(item));
    return h.result();
}

uint64_t lightKey(const Light& l) {
    ContentHash h;
    h.value(l.type);
    for (const Vec3* v : {&l.color, &l.attenuation, &l.position, &l.direction}) h.vec(*v);
    for (double v : {l.angleDegrees, l.penumbraDegrees, l.radius, l.width, l.height}) h.value(v);
    return h.result();
}

// Pairs the elements of two lists (old, fresh) by their keys and kinds, as the header says:
// pair(i, j) for old i matched with fresh j, renew(j) for a fresh element matched with none.
void matchLists(const std::vector<uint64_t>& oldKeys, const std::vector<uint64_t>& freshKeys,
                const std::function<size_t(size_t)>& oldKind, const std::function<size_t(size_t)>& freshKind,
                const std::function<void(size_t, size_t)>& pair, const std::function<void(size_t)>& renew) {
    const size_t n = oldKeys.size(), m = freshKeys.size();
    constexpr size_t kNone = size_t(-1);
    std::vector<size_t> partner(m, kNone);  // of each fresh element, the old one it is paired with
    std::vector<bool> oldPaired(n, false);
    auto join = [&](size_t i, size_t j) {
        partner[j] = i;
        oldPaired[i] = true;
    };
    size_t prefix = 0;
    while (prefix < n && prefix < m && oldKeys[prefix] == freshKeys[prefix]) join(prefix, prefix), ++prefix;
    size_t suffix = 0;
    while (suffix < n - prefix && suffix < m - prefix && oldKeys[n - 1 - suffix] == freshKeys[m - 1 - suffix]) {
        join(n - 1 - suffix, m - 1 - suffix);
        ++suffix;
    }
    // The run between: alike ones, the earliest old one first.
    std::map<uint64_t, std::vector<size_t>> unpaired;  // by key, latest first
    for (size_t i = n - suffix; i-- > prefix;) unpaired[oldKeys[i]].push_back(i);
    for (size_t j = prefix; j < m - suffix; ++j) {
        auto alike = unpaired.find(freshKeys[j]);
        if (alike == unpaired.end() || alike->second.empty()) continue;
        join(alike->second.back(), j);
        alike->second.pop_back();
    }
    // Between two pairs in order (anchors), what is left on both sides is paired in order
    // when as many are left on each: an element edited in place.
    auto pairGap = [&](size_t oldFrom, size_t oldTo, size_t freshFrom, size_t freshTo) {
        std::vector<size_t> oldLeft, freshLeft;
        for (size_t i = oldFrom; i < oldTo; ++i)
            if (!oldPaired[i]) oldLeft.push_back(i);
        for (size_t j = freshFrom; j < freshTo; ++j)
            if (partner[j] == kNone) freshLeft.push_back(j);
        if (oldLeft.size() != freshLeft.size()) return;
        for (size_t k = 0; k < freshLeft.size(); ++k)
            if (oldKind(oldLeft[k]) == freshKind(freshLeft[k])) join(oldLeft[k], freshLeft[k]);
    };
    size_t oldFrom = 0, freshFrom = 0;
    for (size_t j = 0; j < m; ++j) {
        if (partner[j] == kNone || partner[j] < oldFrom) continue;  // unpaired, or crossing an anchor
        pairGap(oldFrom, partner[j], freshFrom, j);
        oldFrom = partner[j] + 1;
        freshFrom = j + 1;
    }
    pairGap(oldFrom, n, freshFrom, m);
    for (size_t j = 0; j < m; ++j) {
        if (partner[j] == kNone) renew(j);
        else pair(partner[j], j);
    }
}

class IdKeeper {
public:
    IdKeeper(const SceneDocument& old, SceneDocument& fresh) : old_(old), fresh_(fresh) {
        nextObject_ = old.nextObjectId;
        nextBlock_ = old.nextBlockId;
        nextNode_ = old.nextNodeId;
    }

    void run() {
        for (NamedTree* tree : treesInOrder(fresh_)) {
            auto was = old_.trees.find(tree->name);
            if (was == old_.trees.end()) {
                tree->id = nextNode_++;
                renewTree(tree->tree);
            } else {
                tree->id = was->second.id;
                matchTrees(was->second.tree, tree->tree);
            }
        }
        matchLights();
        fresh_.nextObjectId = nextObject_;
        fresh_.nextBlockId = nextBlock_;
        fresh_.nextNodeId = nextNode_;
    }

private:
    void matchTrees(const TreeNode& old, TreeNode& fresh) {
        std::vector<uint64_t> oldKeys, freshKeys;
        for (const Block& b : old.blocks) oldKeys.push_back(blockKey(b));
        for (const Block& b : fresh.blocks) freshKeys.push_back(blockKey(b));
        const auto sameKind = [](size_t) { return size_t(0); };
        matchLists(
            oldKeys, freshKeys, sameKind, sameKind,
            [&](size_t i, size_t j) { matchBlocks(old.blocks[i], fresh.blocks[j]); },
            [&](size_t j) { renewBlock(fresh.blocks[j]); });
    }

    void matchBlocks(const Block& old, Block& fresh) {
        fresh.id = old.id;
        std::vector<uint64_t> oldKeys, freshKeys;
        for (const SceneItem& item : old.items) oldKeys.push_back(itemKey(item));
        for (const SceneItem& item : fresh.items) freshKeys.push_back(itemKey(item));
        matchLists(
            oldKeys, freshKeys, [&](size_t i) { return old.items[i].index(); },
            [&](size_t j) { return fresh.items[j].index(); },
            [&](size_t i, size_t j) { matchItems(old.items[i], fresh.items[j]); },
            [&](size_t j) { renewItem(fresh.items[j]); });
    }

    // Of the same kind (matchLists pairs no others).
    void matchItems(const SceneItem& old, SceneItem& fresh) {
        if (auto* p = std::get_if<PrimitiveNode>(&fresh)) p->id = std::get<PrimitiveNode>(old).id;
        else if (auto* m = std::get_if<MasterReference>(&fresh)) m->id = std::get<MasterReference>(old).id;
        else if (auto* t = std::get_if<Box<TreeNode>>(&fresh)) matchTrees(*std::get<Box<TreeNode>>(old), **t);
        else {
            CsgNode& csg = *std::get<Box<CsgNode>>(fresh);
            const CsgNode& was = *std::get<Box<CsgNode>>(old);
            csg.id = was.id;
            for (size_t k = 0; k < csg.operands.size(); ++k) {
                if (k < was.operands.size()) matchTrees(was.operands[k], csg.operands[k]);
                else renewTree(csg.operands[k]);
            }
        }
    }

    void renewTree(TreeNode& tree) {
        for (Block& block : tree.blocks) renewBlock(block);
    }

    void renewBlock(Block& block) {
        block.id = nextBlock_++;
        for (SceneItem& item : block.items) renewItem(item);
    }

    void renewItem(SceneItem& item) {
        if (auto* p = std::get_if<PrimitiveNode>(&item)) p->id = nextObject_++;
        else if (auto* m = std::get_if<MasterReference>(&item)) m->id = nextNode_++;
        else if (auto* t = std::get_if<Box<TreeNode>>(&item)) renewTree(**t);
        else {
            CsgNode& csg = *std::get<Box<CsgNode>>(item);
            csg.id = nextNode_++;
            for (TreeNode& operand : csg.operands) renewTree(operand);
        }
    }

    void matchLights() {
        std::vector<uint64_t> oldKeys, freshKeys;
        for (const Light& l : old_.lights) oldKeys.push_back(lightKey(l));
        for (const Light& l : fresh_.lights) freshKeys.push_back(lightKey(l));
        fresh_.lightIds.assign(fresh_.lights.size(), -1);
        const auto sameKind = [](size_t) { return size_t(0); };
        matchLists(
            oldKeys, freshKeys, sameKind, sameKind,
            [&](size_t i, size_t j) { fresh_.lightIds[j] = i < old_.lightIds.size() ? old_.lightIds[i] : nextNode_++; },
            [&](size_t j) { fresh_.lightIds[j] = nextNode_++; });
    }

    const SceneDocument& old_;
    SceneDocument& fresh_;
    int nextObject_ = 0, nextBlock_ = 0, nextNode_ = 0;
};

}  // namespace

void keepIdsAcrossReload(const SceneDocument& old, SceneDocument& fresh) { IdKeeper(old, fresh).run(); }

}  // namespace ray::edit
