// Collapsing the binary BVH into the kernel's four-wide one, and that into the sixteen-wide
// one of CPU devices (host/accel/wide_bvh.h): every primitive range appears once, every
// child's box holds what lies below it, nodes keep as many children as the tree allows, and
// no path gets longer.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <vector>

#include "accel/bvh.h"
#include "accel/wide_bvh.h"

namespace ray {
namespace {

std::vector<BoundingBox> randomBoxes(uint64_t seed, size_t count) {
    std::mt19937_64 engine(seed);
    std::uniform_real_distribution<float> position(-100, 100), size(0.01f, 5);
    std::vector<BoundingBox> boxes(count);
    for (BoundingBox& b : boxes) {
        for (int a = 0; a < 3; ++a) {
            b.min[a] = position(engine);
            b.max[a] = b.min[a] + size(engine);
        }
    }
    return boxes;
}

float lane(const gpu::float4& v, int c) { return (&v.x)[c]; }
int lane(const gpu::int4& v, int c) { return (&v.x)[c]; }
float lane(const gpu::float16& v, int c) { return v.s[c]; }
int lane(const gpu::int16& v, int c) { return v.s[c]; }

constexpr int widthOf(const gpu::RayWideBvhNode&) { return 4; }
constexpr int widthOf(const gpu::RayCpuBvhNode&) { return RAY_CPU_BVH_WIDTH; }

template <class Node>
BoundingBox childBox(const Node& node, int c) {
    BoundingBox b;
    b.min[0] = lane(node.minX, c), b.max[0] = lane(node.maxX, c);
    b.min[1] = lane(node.minY, c), b.max[1] = lane(node.maxY, c);
    b.min[2] = lane(node.minZ, c), b.max[2] = lane(node.maxZ, c);
    return b;
}

bool contains(const BoundingBox& outer, const BoundingBox& inner) {
    for (int a = 0; a < 3; ++a)
        if (inner.min[a] < outer.min[a] || inner.max[a] > outer.max[a]) return false;
    return true;
}

// Walks a wide tree from the root, checking each child against what lies below it;
// records how often each primitive is reached and the deepest path. A child of count -1 of
// the sixteen-wide tree is a node of the four-wide one, walked by `fourWide`.
template <class Node>
struct WideWalk {
    const std::vector<Node>& nodes;
    const std::vector<BoundingBox>& boxesInBvhOrder;
    std::vector<int> reached;
    std::vector<int> visits;
    int deepest = 0;
    WideWalk<gpu::RayWideBvhNode>* fourWide = nullptr;

    // The box of everything below child c of `node`.
    BoundingBox walk(int node, int depth) {
        REQUIRE(node >= 0);
        REQUIRE(size_t(node) < nodes.size());
        ++visits[size_t(node)];
        deepest = std::max(deepest, depth);
        const Node& n = nodes[size_t(node)];
        BoundingBox all;
        for (int c = 0; c < widthOf(n); ++c) {
            const int index = lane(n.index, c), count = lane(n.count, c);
            if (index < 0) {
                CHECK(childBox(n, c).empty());
                continue;
            }
            BoundingBox below;
            if (count > 0) {
                for (int i = index; i < index + count; ++i) {
                    ++reached[size_t(i)];
                    below.expand(boxesInBvhOrder[size_t(i)]);
                }
            } else if (count < 0) {
                REQUIRE(fourWide);
                CHECK(count == -1);
                below = fourWide->walk(index, depth + 1);
                deepest = std::max(deepest, fourWide->deepest);
            } else {
                below = walk(index, depth + 1);
            }
            CHECK(contains(childBox(n, c), below));
            all.expand(below);
        }
        return all;
    }
};

int binaryDepth(const FlatBvh& bvh, int node = 0) {
    const BinaryBvhNode& n = bvh.nodes[size_t(node)];
    int deepest = 0;
    if (n.links.x >= 0 && n.links.y == 0) deepest = std::max(deepest, 1 + binaryDepth(bvh, n.links.x));
    if (n.links.z >= 0 && n.links.w == 0) deepest = std::max(deepest, 1 + binaryDepth(bvh, n.links.z));
    return deepest;
}

void checkWideTree(const std::vector<BoundingBox>& boxes) {
    FlatBvh bvh = buildBvh(boxes);
    std::vector<gpu::RayWideBvhNode> wide = widenBvh(bvh.nodes);
    std::vector<BoundingBox> ordered;
    for (uint32_t i : bvh.primitiveOrder) ordered.push_back(boxes[i]);
    WideWalk<gpu::RayWideBvhNode> w{wide, ordered, std::vector<int>(boxes.size(), 0),
                                    std::vector<int>(wide.size(), 0)};
    w.walk(0, 0);
    INFO(boxes.size() << " boxes, " << bvh.nodes.size() << " binary nodes, " << wide.size() << " wide nodes");
    CHECK(std::all_of(w.reached.begin(), w.reached.end(), [](int n) { return n == 1; }));
    CHECK(std::all_of(w.visits.begin(), w.visits.end(), [](int n) { return n == 1; }));  // a tree, no orphans
    CHECK(w.deepest <= binaryDepth(bvh));
    // A node has fewer than four children only when all of them are leaves: there was no
    // inner node left to open.
    for (const gpu::RayWideBvhNode& n : wide) {
        int present = 0, inner = 0;
        for (int c = 0; c < 4; ++c) {
            present += lane(n.index, c) >= 0;
            inner += lane(n.index, c) >= 0 && lane(n.count, c) == 0;
        }
        CHECK((present == 4 || inner == 0));
    }
    CHECK(wide.size() <= bvh.nodes.size());

    // The CPU's tree, collapsed from this one, and the four-wide subtrees it leaves as they
    // are (children of count -1).
    std::vector<gpu::RayCpuBvhNode> cpu = widenBvhForCpu(wide);
    WideWalk<gpu::RayWideBvhNode> below{wide, ordered, std::vector<int>(boxes.size(), 0),
                                        std::vector<int>(wide.size(), 0)};
    WideWalk<gpu::RayCpuBvhNode> c{cpu, ordered, std::vector<int>(boxes.size(), 0), std::vector<int>(cpu.size(), 0),
                                   0, &below};
    c.walk(0, 0);
    INFO(cpu.size() << " sixteen-wide nodes");
    for (size_t i = 0; i < boxes.size(); ++i) CHECK(c.reached[i] + below.reached[i] == 1);
    CHECK(std::all_of(c.visits.begin(), c.visits.end(), [](int n) { return n == 1; }));
    CHECK(std::all_of(below.visits.begin(), below.visits.end(), [](int n) { return n <= 1; }));
    CHECK(c.deepest <= w.deepest);
    // Opening an inner child adds at most three children: a node has fewer than fourteen
    // only when all of its inner children are four-wide subtrees (too small for a node of
    // their own) or it has none. A node of its own has at least eight children, the root
    // aside. Absent children come last (the order is the tree's in both trees).
    for (size_t k = 0; k < cpu.size(); ++k) {
        const gpu::RayCpuBvhNode& n = cpu[k];
        int present = 0, inner = 0;
        bool absentSeen = false;
        for (int l = 0; l < RAY_CPU_BVH_WIDTH; ++l) {
            const bool here = lane(n.index, l) >= 0;
            CHECK(!(here && absentSeen));
            absentSeen |= !here;
            present += here;
            inner += here && lane(n.count, l) == 0;
        }
        CHECK((present >= RAY_CPU_BVH_WIDTH - 2 || inner == 0));
        if (k > 0) CHECK(present >= 8);
    }
    CHECK(cpu.size() <= wide.size());
}

TEST_CASE("the wide BVH holds every primitive once, inside its parents' boxes", "[bvh]") {
    for (size_t count : {0, 1, 2, 3, 5, 17, 100, 1000, 20000}) checkWideTree(randomBoxes(count + 7, count));
}

TEST_CASE("the wide BVH of identical boxes", "[bvh]") {
    checkWideTree(std::vector<BoundingBox>(500, randomBoxes(3, 1)[0]));
}

TEST_CASE("the wide BVH of no primitives is a root without children", "[bvh]") {
    std::vector<gpu::RayWideBvhNode> wide = widenBvh(buildBvh({}).nodes);
    REQUIRE(wide.size() == 1);
    for (int c = 0; c < 4; ++c) CHECK(lane(wide[0].index, c) == -1);
    for (const std::vector<gpu::RayCpuBvhNode>& cpu : {widenBvhForCpu(wide), widenBvhForCpu({})}) {
        REQUIRE(cpu.size() == 1);
        for (int c = 0; c < RAY_CPU_BVH_WIDTH; ++c) {
            CHECK(lane(cpu[0].index, c) == -1);
            CHECK(childBox(cpu[0], c).empty());
        }
    }
}

}  // namespace
}  // namespace ray
