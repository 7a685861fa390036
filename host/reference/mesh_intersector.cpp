#include "reference/mesh_intersector.h"

#include <algorithm>
#include <numeric>

namespace ray {

namespace {

constexpr int kMaxLeafSize = 4;
constexpr int kMaxStack = 64;  // median splits: depth ≤ log2(triangles) + 1

// Slab test of a box; the entry distance within [tMin, tMax], or nothing.
template <class Box>
std::optional<double> enterBox(const Box& box, const Vec3& origin, const Vec3& inverse, double tMin, double tMax) {
    for (int axis = 0; axis < 3; ++axis) {
        double t0 = (box.lo[axis] - origin[axis]) * inverse[axis];
        double t1 = (box.hi[axis] - origin[axis]) * inverse[axis];
        if (t0 > t1) std::swap(t0, t1);
        if (!(t0 <= t1)) return std::nullopt;  // NaN: a ray in a slab's plane, treated as a miss
        tMin = std::max(tMin, t0);
        tMax = std::min(tMax, t1);
        if (tMin > tMax) return std::nullopt;
    }
    return tMin;
}

}  // namespace

std::optional<TriangleHit> intersectTriangle(const Vec3& origin, const Vec3& direction, const Vec3& p0,
                                             const Vec3& p1, const Vec3& p2) {
    Vec3 e1 = p1 - p0, e2 = p2 - p0;
    Vec3 pv = cross(direction, e2);
    double det = dot(e1, pv);
    if (det == 0) return std::nullopt;
    double inverseDet = 1 / det;
    Vec3 tv = origin - p0;
    double b1 = dot(tv, pv) * inverseDet;
    if (b1 < 0 || b1 > 1) return std::nullopt;
    Vec3 qv = cross(tv, e1);
    double b2 = dot(direction, qv) * inverseDet;
    if (b2 < 0 || b1 + b2 > 1) return std::nullopt;
    return TriangleHit{dot(e2, qv) * inverseDet, b1, b2};
}

MeshIntersector::MeshIntersector(const TriangleMesh& mesh, bool faceNormals) : mesh_(mesh), faceNormals_(faceNormals) {
    const int count = int(mesh.triangles.size());
    std::vector<Box> boxes(static_cast<size_t>(count));
    std::vector<Vec3> centres(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) {
        Box& b = boxes[size_t(i)];
        for (int k = 0; k < 3; ++k) {
            b.lo = componentMin(b.lo, mesh.corner(size_t(i), k));
            b.hi = componentMax(b.hi, mesh.corner(size_t(i), k));
        }
        centres[size_t(i)] = (b.lo + b.hi) * 0.5;
    }
    order_.resize(size_t(count));
    std::iota(order_.begin(), order_.end(), 0);
    if (count > 0) build(0, count, boxes, centres);
}

int MeshIntersector::build(int begin, int end, const std::vector<Box>& boxes, const std::vector<Vec3>& centres) {
    const int index = int(nodes_.size());
    nodes_.emplace_back();
    Box bounds, centreBounds;
    for (int i = begin; i < end; ++i) {
        const Box& b = boxes[size_t(order_[size_t(i)])];
        bounds.lo = componentMin(bounds.lo, b.lo);
        bounds.hi = componentMax(bounds.hi, b.hi);
        centreBounds.lo = componentMin(centreBounds.lo, centres[size_t(order_[size_t(i)])]);
        centreBounds.hi = componentMax(centreBounds.hi, centres[size_t(order_[size_t(i)])]);
    }
    nodes_[size_t(index)].bounds = bounds;
    if (end - begin <= kMaxLeafSize) {
        nodes_[size_t(index)].first = begin;
        nodes_[size_t(index)].count = end - begin;
        return index;
    }
    Vec3 spread = centreBounds.hi - centreBounds.lo;
    int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
    int middle = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                     [&](int a, int b) { return centres[size_t(a)][axis] < centres[size_t(b)][axis]; });
    int left = build(begin, middle, boxes, centres);
    int right = build(middle, end, boxes, centres);
    nodes_[size_t(index)].left = left;
    nodes_[size_t(index)].right = right;
    return index;
}

std::optional<ShapeHit> MeshIntersector::intersect(const Vec3& origin, const Vec3& direction, double tMin,
                                                   double tMax) const {
    if (nodes_.empty()) return std::nullopt;
    Vec3 inverse{1 / direction.x, 1 / direction.y, 1 / direction.z};
    int stack[kMaxStack];
    int size = 0;
    stack[size++] = 0;
    int bestTriangle = -1;
    TriangleHit best{tMax, 0, 0};
    while (size > 0) {
        const Node& node = nodes_[size_t(stack[--size])];
        if (!enterBox(node.bounds, origin, inverse, tMin, best.t)) continue;
        if (node.count > 0) {
            for (int i = node.first; i < node.first + node.count; ++i) {
                size_t triangle = size_t(order_[size_t(i)]);
                auto hit = intersectTriangle(origin, direction, mesh_.corner(triangle, 0), mesh_.corner(triangle, 1),
                                             mesh_.corner(triangle, 2));
                if (hit && hit->t > tMin && hit->t < best.t) {
                    best = *hit;
                    bestTriangle = int(triangle);
                }
            }
            continue;
        }
        stack[size++] = node.right;
        stack[size++] = node.left;
    }
    if (bestTriangle < 0) return std::nullopt;
    ShapeHit hit;
    hit.t = best.t;
    hit.normal = faceNormals_ ? mesh_.faceNormal(size_t(bestTriangle))
                              : mesh_.shadingNormal(size_t(bestTriangle), best.b1, best.b2);
    auto uv = mesh_.texCoordAt(size_t(bestTriangle), best.b1, best.b2);
    hit.uv = {uv[0], uv[1]};
    hit.tangent = mesh_.uTangent(size_t(bestTriangle));
    // Handedness is about the face normal; a shading normal (vn) facing the other way
    // reverses it.
    double facing = dot(hit.normal, mesh_.faceNormal(size_t(bestTriangle))) < 0 ? -1.0 : 1.0;
    hit.bitangentSign = mesh_.uvHandedness(size_t(bestTriangle)) * facing;
    return hit;
}

}  // namespace ray
