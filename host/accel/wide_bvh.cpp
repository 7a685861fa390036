#include "accel/wide_bvh.h"

#include <array>
#include <cstddef>
#include <utility>

#include "accel/bvh.h"

namespace ray {

using std::size_t;

namespace {

// A child as a node of the binary (or the four-wide) tree describes it: its box, and its
// (index, count) link. The default is an absent child: index -1 and an empty box
// (min 1e30 > max -1e30), as the wide node stores one.
struct BinaryChild {
    BoundingBox box;
    int index = -1, count = 0;

    bool absent() const { return index < 0; }
    bool inner() const { return index >= 0 && count == 0; }
};

// Child c (0: left, 1: right) of a binary node; lanes of xBounds are
// (left.min.x, right.min.x, left.max.x, right.max.x), and so on for y and z.
BinaryChild binaryChild(const BinaryBvhNode& node, int c) {
    const gpu::float4* bounds[3] = {&node.xBounds, &node.yBounds, &node.zBounds};
    BinaryChild child;
    for (int a = 0; a < 3; ++a) {
        child.box.min[a] = c == 0 ? bounds[a]->x : bounds[a]->y;
        child.box.max[a] = c == 0 ? bounds[a]->z : bounds[a]->w;
    }
    child.index = c == 0 ? node.links.x : node.links.z;
    child.count = c == 0 ? node.links.y : node.links.w;
    return child;
}

// Up to four children, in the binary tree's order.
struct WideChildren {
    std::array<BinaryChild, 4> child;
    int count = 0;

    void insert(int at, const BinaryChild& c) {
        for (int i = count; i > at; --i) child[size_t(i)] = child[size_t(i - 1)];
        child[size_t(at)] = c;
        ++count;
    }
    void erase(int at) {
        for (int i = at; i + 1 < count; ++i) child[size_t(i)] = child[size_t(i + 1)];
        --count;
    }
};

// The children of the wide node standing for binary node `node`. Fixed arrays, no heap: a
// large scene has millions of nodes.
WideChildren gatherChildren(const std::vector<BinaryBvhNode>& binary, int node) {
    WideChildren children;
    for (int c = 0; c < 2; ++c)
        if (BinaryChild child = binaryChild(binary[size_t(node)], c); !child.absent())
            children.insert(children.count, child);
    while (children.count < 4) {
        int open = -1;
        for (int i = 0; i < children.count; ++i)
            if (children.child[size_t(i)].inner() &&
                (open < 0 || children.child[size_t(i)].box.surfaceArea() >
                                 children.child[size_t(open)].box.surfaceArea()))
                open = i;
        if (open < 0) break;  // only leaves left
        const int opened = children.child[size_t(open)].index;
        children.erase(open);
        for (int c = 0; c < 2; ++c)
            if (BinaryChild child = binaryChild(binary[size_t(opened)], c); !child.absent())
                children.insert(open++, child);  // in the binary tree's order
    }
    return children;
}

void setLane(gpu::float4& v, int lane, float value) { (&v.x)[lane] = value; }
void setLane(gpu::int4& v, int lane, int value) { (&v.x)[lane] = value; }
void setLane(gpu::float16& v, int lane, float value) { v.s[lane] = value; }
void setLane(gpu::int16& v, int lane, int value) { v.s[lane] = value; }

// Child c of a four-wide node, as a BinaryChild (its box and link).
BinaryChild wideChild(const gpu::RayWideBvhNode& node, int c) {
    BinaryChild child;
    child.box.min[0] = (&node.minX.x)[c];
    child.box.min[1] = (&node.minY.x)[c];
    child.box.min[2] = (&node.minZ.x)[c];
    child.box.max[0] = (&node.maxX.x)[c];
    child.box.max[1] = (&node.maxY.x)[c];
    child.box.max[2] = (&node.maxZ.x)[c];
    child.index = (&node.index.x)[c];
    child.count = (&node.count.x)[c];
    return child;
}

// Writes `child` into lane `lane` of a wide node of either width; an inner child gets the
// next slot of `table` (its own node, written later from `pending`).
template <class Node, class Table>
void writeChild(Node& out, int lane, const BinaryChild& child, Table& table,
                std::vector<std::pair<int, size_t>>& pending) {
    setLane(out.minX, lane, child.box.min[0]);
    setLane(out.minY, lane, child.box.min[1]);
    setLane(out.minZ, lane, child.box.min[2]);
    setLane(out.maxX, lane, child.box.max[0]);
    setLane(out.maxY, lane, child.box.max[1]);
    setLane(out.maxZ, lane, child.box.max[2]);
    setLane(out.count, lane, child.count);
    if (child.inner()) {
        setLane(out.index, lane, int(table.size()));
        pending.emplace_back(child.index, table.size());
        table.emplace_back();
    } else {
        setLane(out.index, lane, child.index);
    }
}

// The fewest children a subtree's node of its own must have: a smaller subtree stays in the
// four-wide tree, which the walk enters there (a child of count -1). Sixteen-wide nodes of
// every subtree made 10⁵ spheres' tree 26,148 nodes (13.4 MB), 18,619 of them of two
// children: the binned SAH splits spheres down to one a leaf, so that the four-wide tree's
// lowest nodes hold two.
constexpr int kCpuNodeMinChildren = 8;

// Up to sixteen children, in the tree's order.
struct CpuChildren {
    std::array<BinaryChild, RAY_CPU_BVH_WIDTH> child;
    int count = 0;
};

// How many children four-wide node `node` has (absent ones last).
int presentChildren(const gpu::RayWideBvhNode& node) {
    int present = 0;
    while (present < 4 && (&node.index.x)[present] >= 0) ++present;
    return present;
}

// The children of the sixteen-wide node standing for four-wide node `node`. Fixed arrays,
// no heap: a large scene has hundreds of thousands of nodes.
CpuChildren gatherCpuChildren(const std::vector<gpu::RayWideBvhNode>& wide, int node) {
    CpuChildren children;
    for (int c = 0; c < presentChildren(wide[size_t(node)]); ++c)
        children.child[size_t(children.count++)] = wideChild(wide[size_t(node)], c);
    while (true) {
        int open = -1;
        for (int i = 0; i < children.count; ++i) {
            const BinaryChild& c = children.child[size_t(i)];
            if (!c.inner() || children.count - 1 + presentChildren(wide[size_t(c.index)]) > RAY_CPU_BVH_WIDTH)
                continue;
            if (open < 0 || c.box.surfaceArea() > children.child[size_t(open)].box.surfaceArea()) open = i;
        }
        if (open < 0) return children;  // only leaves, or no inner child whose children fit
        const gpu::RayWideBvhNode& opened = wide[size_t(children.child[size_t(open)].index)];
        const int added = presentChildren(opened);
        // child `open` gives way to its `added` children, in their order
        for (int i = children.count - 1; i > open; --i)
            children.child[size_t(i + added - 1)] = children.child[size_t(i)];
        for (int c = 0; c < added; ++c) children.child[size_t(open + c)] = wideChild(opened, c);
        children.count += added - 1;
    }
}

}  // namespace

std::vector<gpu::RayWideBvhNode> widenBvh(const std::vector<BinaryBvhNode>& binary) {
    std::vector<gpu::RayWideBvhNode> wide;
    if (binary.empty()) return wide;
    wide.reserve(binary.size() / 2 + 1);
    // (binary node, its wide node's slot), depth first: a parent is written before its
    // children, and a subtree's nodes lie together.
    std::vector<std::pair<int, size_t>> pending{{0, 0}};
    wide.emplace_back();
    while (!pending.empty()) {
        auto [node, slot] = pending.back();
        pending.pop_back();
        const WideChildren children = gatherChildren(binary, node);
        gpu::RayWideBvhNode out{};
        for (int c = 0; c < 4; ++c)
            writeChild(out, c, c < children.count ? children.child[size_t(c)] : BinaryChild{}, wide, pending);
        wide[slot] = out;
    }
    return wide;
}

std::vector<gpu::RayCpuBvhNode> widenBvhForCpu(const std::vector<gpu::RayWideBvhNode>& wide) {
    std::vector<gpu::RayCpuBvhNode> cpu;
    std::vector<std::pair<int, size_t>> pending;  // (four-wide node, its sixteen-wide slot)
    cpu.emplace_back();
    if (wide.empty()) {  // no tree: a root whose children are all absent
        for (int c = 0; c < RAY_CPU_BVH_WIDTH; ++c) writeChild(cpu[0], c, BinaryChild{}, cpu, pending);
        return cpu;
    }
    // gathered[k]: the children of pending[k]'s node, found once, when its parent decided
    // whether it gets a node of its own
    std::vector<CpuChildren> gathered{gatherCpuChildren(wide, 0)};
    pending.emplace_back(0, 0);
    while (!pending.empty()) {
        const size_t slot = pending.back().second;
        const CpuChildren children = gathered.back();
        pending.pop_back();
        gathered.pop_back();
        gpu::RayCpuBvhNode out{};
        for (int c = 0; c < RAY_CPU_BVH_WIDTH; ++c) {
            BinaryChild child = c < children.count ? children.child[size_t(c)] : BinaryChild{};
            if (child.inner()) {
                CpuChildren below = gatherCpuChildren(wide, child.index);
                if (below.count < kCpuNodeMinChildren)
                    child.count = -1;  // the four-wide node itself: written as a leaf is, index and all
                else
                    gathered.push_back(below);  // beside the pending entry writeChild adds
            }
            writeChild(out, c, child, cpu, pending);
        }
        cpu[slot] = out;
    }
    return cpu;
}

}  // namespace ray
