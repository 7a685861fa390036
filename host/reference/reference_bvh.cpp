#include "reference/reference_bvh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "reference/csg.h"

namespace ray::reference {

namespace {

// Leaves hold at most this many primitives.
constexpr int kMaxLeafSize = 4;

// Median splits halve the primitive count at every level, so the tree is at most
// log2(n) + 1 levels deep and the traversal stack never holds more than that many
// entries: 64 is enough for any scene that fits in memory.
constexpr int kMaxStack = 64;

// Boxes are grown by this fraction of their size and position: their corners were
// computed in floating point, and a ray grazing a primitive's extreme point must not be
// culled by a box rounded a hair too small (the brute-force search would find that hit).
constexpr double kBoundsPadding = 1e-9;

Aabb padded(const Aabb& box) {
    double magnitude = std::max(maxComponent(box.hi - box.lo),
                                std::max(maxComponent(componentMax(box.hi, -box.hi)),
                                         maxComponent(componentMax(box.lo, -box.lo))));
    Vec3 pad{1, 1, 1};
    pad *= kBoundsPadding * magnitude;
    return {box.lo - pad, box.hi + pad};
}

}  // namespace

int Aabb::longestAxis() const {
    Vec3 size = hi - lo;
    if (size.x >= size.y && size.x >= size.z) return 0;
    return size.y >= size.z ? 1 : 2;
}

Aabb worldBounds(const PrimitiveInstance& instance) {
    Aabb box;
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 &lo = instance.objectLo, &hi = instance.objectHi;
        Vec3 p{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z};
        Vec3 start = instance.objectToWorld.transformPoint(p);
        box.grow(start);
        box.grow(start + instance.motion);  // where the corner is at the end of the shutter
    }
    return padded(box);
}

std::optional<double> intersectBox(const Aabb& box, const Vec3& origin, const Vec3& direction, double tMin,
                                   double tMax) {
    for (int axis = 0; axis < 3; ++axis) {
        double o = origin[axis], d = direction[axis];
        if (d == 0) {
            // Parallel to the slab: within it everywhere or nowhere. (Dividing would give
            // 0·∞ = NaN for an origin on the slab's plane.)
            if (o < box.lo[axis] || o > box.hi[axis]) return std::nullopt;
            continue;
        }
        double t0 = (box.lo[axis] - o) / d, t1 = (box.hi[axis] - o) / d;
        if (t0 > t1) std::swap(t0, t1);
        tMin = std::max(tMin, t0);
        tMax = std::min(tMax, t1);
        if (tMin > tMax) return std::nullopt;
    }
    return tMin;
}

SceneIntersector::SceneIntersector(const Scene& scene, SceneSearch search, bool courseMeshes)
    : scene_(scene), primitives_(scene.primitives), search_(search), courseMeshes_(courseMeshes) {
    meshes_.reserve(scene.meshes.size());
    for (const TriangleMesh& mesh : scene.meshes) meshes_.emplace_back(mesh, courseMeshes);
    if (courseMeshes) {
        for (const PrimitiveInstance& instance : primitives_) {
            if (instance.type != PrimitiveType::Mesh) continue;
            double frobenius = std::sqrt(dot(instance.objectToWorld.transformVector({1, 0, 0}),
                                             instance.objectToWorld.transformVector({1, 0, 0})) +
                                         dot(instance.objectToWorld.transformVector({0, 1, 0}),
                                             instance.objectToWorld.transformVector({0, 1, 0})) +
                                         dot(instance.objectToWorld.transformVector({0, 0, 1}),
                                             instance.objectToWorld.transformVector({0, 0, 1})));
            meshKeyStretch_ = std::max(meshKeyStretch_, frobenius * (1 + 1e-6));
        }
    }
    const int count = int(primitives_.size());
    std::vector<Aabb> boxes(count);
    std::vector<Vec3> centres(count);
    for (int i = 0; i < count; ++i) {
        boxes[i] = worldBounds(primitives_[i]);
        centres[i] = boxes[i].centre();
        sceneBounds_.grow(boxes[i]);
    }
    order_.resize(count);
    std::iota(order_.begin(), order_.end(), 0);
    if (search_ == SceneSearch::Bvh && count > 0) {
        nodes_.reserve(size_t(2 * count / kMaxLeafSize + 1));
        build(0, count, boxes, centres);
    }
}

// Builds the subtree over order_[begin, end) and returns its node's index.
int SceneIntersector::build(int begin, int end, const std::vector<Aabb>& boxes, const std::vector<Vec3>& centres) {
    const int index = int(nodes_.size());
    nodes_.emplace_back();
    Aabb bounds, centreBounds;
    for (int i = begin; i < end; ++i) {
        bounds.grow(boxes[order_[i]]);
        centreBounds.grow(centres[order_[i]]);
    }
    nodes_[index].bounds = bounds;

    if (end - begin <= kMaxLeafSize) {
        nodes_[index].first = begin;
        nodes_[index].count = end - begin;
        return index;
    }

    // Median split along the axis where the centres spread most. nth_element puts the
    // median in place with the smaller centres before it and the larger after.
    const int axis = centreBounds.longestAxis();
    const int middle = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                     [&](int a, int b) { return centres[a][axis] < centres[b][axis]; });
    const int left = build(begin, middle, boxes, centres);
    const int right = build(middle, end, boxes, centres);
    nodes_[index].left = left;  // not through a reference: build() grows nodes_
    nodes_[index].right = right;
    return index;
}

std::optional<SceneHit> SceneIntersector::intersectPrimitive(int index, const Vec3& rayOrigin, const Vec3& direction,
                                                             double tMin, double tMax, double time) const {
    // Object space through the inverse transform. The direction is not renormalized,
    // so t means the same distance along the ray in both spaces. An instance moved by
    // time·motion is the same as the ray moved back by it.
    const PrimitiveInstance& instance = primitives_[index];
    const Vec3 origin = rayOrigin - time * instance.motion;
    auto found = [index](std::optional<ShapeHit> hit) {
        return hit ? std::optional<SceneHit>(SceneHit{index, *hit}) : std::nullopt;
    };
    if (instance.type == PrimitiveType::Csg) {
        auto hit = intersectCsg(scene_, scene_.csgObjects[size_t(instance.csg)], origin, direction, tMin, tMax);
        return hit ? std::optional<SceneHit>(SceneHit{index, hit->local, hit->operand}) : std::nullopt;
    }
    if (instance.type == PrimitiveType::Mesh)
        return found(meshes_[size_t(instance.mesh)].intersect(instance.worldToObject.transformPoint(origin),
                                                              instance.worldToObject.transformVector(direction), tMin,
                                                              tMax));
    return found(intersectUnitPrimitive(instance.type, instance.worldToObject.transformPoint(origin),
                                        instance.worldToObject.transformVector(direction), tMin, tMax));
}

template <class Test>
void SceneIntersector::traverse(const Vec3& origin, const Vec3& direction, double tMin, double tMax,
                                double stretch, Test&& test) const {
    if (search_ == SceneSearch::BruteForce) {
        for (int i = 0; i < int(primitives_.size()) && tMax >= 0; ++i) tMax = test(i, tMax);
        return;
    }
    if (nodes_.empty()) return;

    // Depth first, nearer child first, skipping subtrees that start beyond the nearest
    // hit found so far. Each entry remembers where the ray enters its box.
    struct Entry {
        int node;
        double tEnter;
    };
    Entry stack[kMaxStack];
    int size = 0;
    if (auto t = intersectBox(nodes_[0].bounds, origin, direction, tMin, tMax * stretch)) stack[size++] = {0, *t};

    while (size > 0) {
        const Entry entry = stack[--size];
        if (entry.tEnter > tMax * stretch) continue;
        const Node& node = nodes_[entry.node];
        if (node.count > 0) {
            for (int i = node.first; i < node.first + node.count; ++i) {
                tMax = test(order_[i], tMax);
                if (tMax < 0) return;
            }
            continue;
        }
        auto tLeft = intersectBox(nodes_[node.left].bounds, origin, direction, tMin, tMax * stretch);
        auto tRight = intersectBox(nodes_[node.right].bounds, origin, direction, tMin, tMax * stretch);
        // Push the farther child first so that the nearer one is visited first.
        if (tLeft && tRight && *tLeft < *tRight) {
            stack[size++] = {node.right, *tRight};
            stack[size++] = {node.left, *tLeft};
        } else {
            if (tLeft) stack[size++] = {node.left, *tLeft};
            if (tRight) stack[size++] = {node.right, *tRight};
        }
    }
}

std::optional<SceneHit> SceneIntersector::closestHit(const Vec3& origin, const Vec3& direction, double tMin,
                                                     double tMax, double time) const {
    std::optional<SceneHit> best;
    const double stretch = courseMeshes_ ? meshKeyStretch_ : 1.0;
    traverse(origin, direction, tMin, tMax, stretch, [&](int primitive, double tLimit) {
        // Coplanar faces (a chessboard's squares flush with its border) are hit at exactly
        // the same distance. Such a tie goes to the primitive listed last in the scene, as
        // the course's renders show (SPEC §4), whatever order the BVH or brute force visits
        // the primitives in.
        double limit = best && primitive > best->primitive ? std::nextafter(tLimit, INFINITY) : tLimit;
        if (courseMeshes_ && primitives_[primitive].type == PrimitiveType::Mesh) {
            // The course's key t_obj = t·scale: a key below limit is a world t below
            // limit/scale; the hit's t becomes the key (the course's hit point).
            const double scale =
                length(primitives_[primitive].worldToObject.transformVector(direction)) / length(direction);
            auto hit = intersectPrimitive(primitive, origin, direction, tMin, limit / scale, time);
            if (!hit || !(hit->local.t * scale < limit)) return tLimit;
            hit->local.t *= scale;
            best = *hit;
            return hit->local.t;
        }
        if (auto hit = intersectPrimitive(primitive, origin, direction, tMin, limit, time)) {
            best = *hit;
            return hit->local.t;
        }
        return tLimit;
    });
    return best;
}

bool SceneIntersector::anyHit(const Vec3& origin, const Vec3& direction, double tMin, double tMax,
                              double time) const {
    bool found = false;
    traverse(origin, direction, tMin, tMax, 1.0, [&](int primitive, double tLimit) {
        if (intersectPrimitive(primitive, origin, direction, tMin, tLimit, time)) {
            found = true;
            return -1.0;  // stop: one blocker is enough
        }
        return tLimit;
    });
    return found;
}

}  // namespace ray::reference
