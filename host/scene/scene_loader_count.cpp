// Pass 2 of the scene loader (scene_loader.cpp): instances counted per tree, masters
// resolved, cycles and too deep nesting found, before a single instance is made.
#include "scene/scene_loader_passes.h"

#include <algorithm>
#include <limits>

namespace ray::loader {
namespace {

// ---------------------------------------------------------------------------------------
// Pass 2: counting instances, resolving masters, finding cycles

uint64_t saturatingAdd(uint64_t a, uint64_t b) {
    return a > std::numeric_limits<uint64_t>::max() - b ? std::numeric_limits<uint64_t>::max() : a + b;
}

class InstanceCounter {
public:
    InstanceCounter(const Diagnostics& diagnostics, std::map<std::string, NamedTree>& trees)
        : diagnostics_(diagnostics), trees_(trees) {}

    // Counts every top-level tree, so that a bad master is reported even in a tree the
    // scene does not use.
    void countAll() {
        for (auto& [name, tree] : trees_) tree.state = NamedTree::State::Uncounted;
        for (auto& [name, tree] : trees_) count(tree, tree.line);
    }

    uint64_t count(NamedTree& tree, int referenceLine) {
        if (tree.state == NamedTree::State::Counted) {
            noteLevel(depth_ + tree.levels, referenceLine);  // a tree counted before, reached deeper
            return tree.instances;
        }
        if (tree.state == NamedTree::State::Counting) reportCycle(tree, referenceLine);
        tree.state = NamedTree::State::Counting;
        path_.push_back(&tree);
        const int entryDepth = depth_, deepestOutside = deepest_;
        deepest_ = depth_;
        tree.instances = count(tree.tree, referenceLine);
        tree.levels = deepest_ - entryDepth;
        deepest_ = std::max(deepest_, deepestOutside);
        path_.pop_back();
        tree.state = NamedTree::State::Counted;
        return tree.instances;
    }

private:
    uint64_t count(TreeNode& node, int line) {
        noteLevel(++depth_, line);
        uint64_t total = 0;
        for (Block& block : node.blocks)
            for (SceneItem& item : block.items) total = saturatingAdd(total, count(item, line));
        --depth_;
        return total;
    }

    void noteLevel(int level, int line) {
        deepest_ = std::max(deepest_, level);
        if (level > kMaxNestingLevels)
            diagnostics_.error(line, "trees and masters nest more than " + std::to_string(kMaxNestingLevels) +
                                         " levels deep",
                               "flatten the hierarchy (fewer levels of masters or nested trees)");
    }

    uint64_t count(SceneItem& item, int line) {
        if (std::holds_alternative<PrimitiveNode>(item)) return 1;
        if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) return count(**subtree, line);
        if (auto* csg = std::get_if<Box<CsgNode>>(&item)) {
            uint64_t total = 0;
            for (TreeNode& operand : (*csg)->operands) total = saturatingAdd(total, count(operand, line));
            return total;
        }
        MasterReference& master = std::get<MasterReference>(item);
        auto it = trees_.find(master.name);
        if (it == trees_.end())
            diagnostics_.error(master.line, "no tree named '" + master.name + "' for this master (trees: " +
                                                treeNames() + ")",
                               "define <object type=\"tree\" name=\"" + master.name +
                                   "\"> at the top level, or fix the name");
        master.target = &it->second;
        return count(it->second, master.line);
    }

    [[noreturn]] void reportCycle(const NamedTree& tree, int line) const {
        std::vector<std::string> cycle;
        bool inCycle = false;
        for (const NamedTree* step : path_) {
            inCycle = inCycle || step == &tree;
            if (inCycle) cycle.push_back(step->name);
        }
        cycle.push_back(tree.name);
        diagnostics_.error(line, "cyclic master reference: " + joined(cycle, " -> "),
                           "a tree cannot contain itself; break the cycle");
    }

    std::string treeNames() const {
        std::vector<std::string> names;
        for (const auto& [name, tree] : trees_) names.push_back(name);
        return joined(names, ", ");
    }

    const Diagnostics& diagnostics_;
    std::map<std::string, NamedTree>& trees_;
    std::vector<const NamedTree*> path_;  // the trees being counted, outermost first
    int depth_ = 0;                        // tree levels entered on the current path
    int deepest_ = 0;                      // the deepest level reached in the tree being counted
};

}  // namespace

void countInstances(std::map<std::string, NamedTree>& trees, const Diagnostics& diagnostics) {
    InstanceCounter(diagnostics, trees).countAll();
}

}  // namespace ray::loader
