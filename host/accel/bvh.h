// The bounding volume hierarchy over primitive instances: built on the host with the
// binned surface-area heuristic and flattened into an array of two-wide nodes, which the
// host walks itself (its tests) and collapses into the wide trees the kernel walks
// (accel/wide_bvh.h, cl/shared_types.h RayWideBvhNode).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/math.h"
#include "scene/scene.h"
#include "shared_types.h"

namespace ray {

// An axis-aligned box in float, the precision the nodes store.
struct BoundingBox {
    float min[3] = {1e30f, 1e30f, 1e30f};
    float max[3] = {-1e30f, -1e30f, -1e30f};

    bool empty() const { return min[0] > max[0]; }
    void expand(const BoundingBox& b);
    float surfaceArea() const;
};

// The world-space box of a primitive instance, rounded outward to float so that it
// contains the exact (double) primitive; a moving one's covers its whole motion (the
// union of its boxes at shutter times 0 and 1).
BoundingBox worldBounds(const PrimitiveInstance& primitive);

// A node of the flattened two-wide BVH: 64 bytes, one cache line.
//
// A node stores the bounds of its two children rather than its own, so one fetch tests
// both children (and decides which to visit first): the lanes of xBounds are (left.min.x,
// right.min.x, left.max.x, right.max.x), and so on for y and z.
//
// links: (leftIndex, leftCount, rightIndex, rightCount). A count of 0 means the index is
// that of an inner node; a count > 0 means a leaf holding primitives [index, index + count)
// of BVH order (FlatBvh::primitiveOrder). An absent child (a scene of one primitive) has
// index -1 and empty bounds (min > max). Node 0 is the root.
struct BinaryBvhNode {
    gpu::float4 xBounds;
    gpu::float4 yBounds;
    gpu::float4 zBounds;
    gpu::int4 links;
};

struct FlatBvh {
    std::vector<BinaryBvhNode> nodes;  // node 0 is the root
    // primitiveOrder[i]: the input index of the primitive at position i of BVH order (the
    // leaves' ranges index positions in this order).
    std::vector<uint32_t> primitiveOrder;
};

// No root-to-leaf path holds more than this many inner nodes (the builder falls back to
// median splits near the limit), so a traversal stack of this many entries never
// overflows: the host walk below and the kernel's use a fixed array of this size.
constexpr int kBvhMaxDepth = 64;

struct BvhBuildOptions {
    int maxLeafSize = 4;
    // Primitives a leaf tests at once (a mesh's triangles, four to a record): a leaf of n
    // costs ceil(n / leafBlock) tests in the surface-area heuristic.
    int leafBlock = 1;
    int bins = 16;
    // The most inner nodes on any root-to-leaf path, capped at kBvhMaxDepth; it holds for
    // up to 2^maxDepth primitives. Lowered only by the tests of that guard.
    int maxDepth = kBvhMaxDepth;
    // The threads the build may use; 0: one a core. The tree is the same for every count
    // (the tests build it with several): only how fast it is built depends on it.
    int threads = 0;
};

// Builds the hierarchy over the boxes (one per primitive). An empty input gives a root
// with two absent children.
FlatBvh buildBvh(const std::vector<BoundingBox>& primitiveBounds, const BvhBuildOptions& options = {});

// Host traversals of the flattened array, the same walk the kernel makes; used by tests
// against brute force, and usable by any host code that wants the BVH.
//
// intersect(position, tMax) tests the primitive at `position` of BVH order and returns its
// hit distance in (tMin, tMax), or a negative value for a miss.
using PrimitiveTest = std::function<double(uint32_t position, double tMax)>;

// The closest hit below tMax: returns the BVH-order position of the primitive hit, or -1,
// and sets *tHit.
int64_t bvhClosestHit(const FlatBvh& bvh, const Vec3& origin, const Vec3& direction, double tMax,
                      const PrimitiveTest& intersect, double* tHit);

// Whether anything is hit below tMax (shadow rays): stops at the first hit found.
bool bvhAnyHit(const FlatBvh& bvh, const Vec3& origin, const Vec3& direction, double tMax,
               const PrimitiveTest& intersect);

}  // namespace ray
