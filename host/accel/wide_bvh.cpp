#include "accel/wide_bvh.h"

#include <array>
#include <cstddef>
#include <utility>

#include "accel/bvh.h"

namespace ray {

using std::size_t;

namespace {

// A child as a binary node describes it: its box, and its (index, count) link. The default
// is an absent child: index -1 and an empty box (min 1e30 > max -1e30), as the wide node
// stores one.
struct BinaryChild {
    BoundingBox box;
    int index = -1, count = 0;

    bool absent() const { return index < 0; }
    bool inner() const { return index >= 0 && count == 0; }
};

// Child c (0: left, 1: right) of a binary node; lanes of xBounds are
// (left.min.x, right.min.x, left.max.x, right.max.x), and so on for y and z.
BinaryChild binaryChild(const gpu::RayBvhNode& node, int c) {
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
WideChildren gatherChildren(const std::vector<gpu::RayBvhNode>& binary, int node) {
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

}  // namespace

std::vector<gpu::RayWideBvhNode> widenBvh(const std::vector<gpu::RayBvhNode>& binary) {
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
        gpu::RayWideBvhNode out;
        for (int c = 0; c < 4; ++c) {
            const BinaryChild child = c < children.count ? children.child[size_t(c)] : BinaryChild{};
            setLane(out.minX, c, child.box.min[0]);
            setLane(out.minY, c, child.box.min[1]);
            setLane(out.minZ, c, child.box.min[2]);
            setLane(out.maxX, c, child.box.max[0]);
            setLane(out.maxY, c, child.box.max[1]);
            setLane(out.maxZ, c, child.box.max[2]);
            setLane(out.count, c, child.count);
            if (child.inner()) {
                setLane(out.index, c, int(wide.size()));
                pending.emplace_back(child.index, wide.size());
                wide.emplace_back();
            } else {
                setLane(out.index, c, child.index);
            }
        }
        wide[slot] = out;
    }
    return wide;
}

}  // namespace ray
