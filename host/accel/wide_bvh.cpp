#include "accel/wide_bvh.h"

#include <array>
#include <cstddef>
#include <utility>

namespace ray {

using std::size_t;

namespace {

// A child as a binary node describes it: its box, and its (index, count) link.
struct BinaryChild {
    float min[3] = {}, max[3] = {};
    int index = -1, count = 0;

    bool absent() const { return index < 0; }
    bool inner() const { return index >= 0 && count == 0; }
    // Half the surface area: only comparisons between children matter.
    float halfArea() const {
        float d[3];
        for (int a = 0; a < 3; ++a) d[a] = max[a] > min[a] ? max[a] - min[a] : 0.0f;
        return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
    }
};

// Child c (0: left, 1: right) of a binary node; lanes of xBounds are
// (left.min.x, right.min.x, left.max.x, right.max.x), and so on for y and z.
BinaryChild binaryChild(const gpu::RayBvhNode& node, int c) {
    const gpu::float4* bounds[3] = {&node.xBounds, &node.yBounds, &node.zBounds};
    BinaryChild child;
    for (int a = 0; a < 3; ++a) {
        child.min[a] = c == 0 ? bounds[a]->x : bounds[a]->y;
        child.max[a] = c == 0 ? bounds[a]->z : bounds[a]->w;
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
                (open < 0 || children.child[size_t(i)].halfArea() > children.child[size_t(open)].halfArea()))
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
            // Absent: an empty box (min > max) and index -1.
            const BinaryChild child = c < children.count ? children.child[size_t(c)] : BinaryChild{};
            const bool present = !child.absent();
            setLane(out.minX, c, present ? child.min[0] : 1e30f);
            setLane(out.minY, c, present ? child.min[1] : 1e30f);
            setLane(out.minZ, c, present ? child.min[2] : 1e30f);
            setLane(out.maxX, c, present ? child.max[0] : -1e30f);
            setLane(out.maxY, c, present ? child.max[1] : -1e30f);
            setLane(out.maxZ, c, present ? child.max[2] : -1e30f);
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
