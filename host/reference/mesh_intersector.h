// Ray–mesh intersection for the reference renderer: a plain median-split BVH over one
// mesh's triangles in double precision, and Möller–Trumbore triangle tests. One is built
// per mesh (not per instance); instances carry the ray into the mesh's object space.
#pragma once

#include <optional>
#include <vector>

#include "scene/mesh.h"
#include "reference/shapes.h"

namespace ray {

class MeshIntersector {
public:
    // faceNormals (--course-meshes): hits carry the triangle's face normal, not the
    // interpolated vn.
    explicit MeshIntersector(const TriangleMesh& mesh, bool faceNormals = false);

    // The nearest hit with tMin < t < tMax in the mesh's object space: the shading normal
    // (smooth where the file gives vn, the face normal with faceNormals) and the texture
    // coordinates at the hit.
    std::optional<ShapeHit> intersect(const Vec3& origin, const Vec3& direction, double tMin, double tMax) const;

private:
    struct Box {
        Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    };
    struct Node {
        Box bounds;
        int first = 0, count = 0;   // a leaf: triangles order_[first, first + count)
        int left = -1, right = -1;  // an inner node
    };
    int build(int begin, int end, const std::vector<Box>& boxes, const std::vector<Vec3>& centres);

    const TriangleMesh& mesh_;
    bool faceNormals_ = false;
    std::vector<Node> nodes_;
    std::vector<int> order_;
};

// Möller–Trumbore: the distance t along the ray and barycentrics (b1, b2) of corners 1 and
// 2, or nothing for a miss or a ray in the triangle's plane.
struct TriangleHit {
    double t, b1, b2;
};
std::optional<TriangleHit> intersectTriangle(const Vec3& origin, const Vec3& direction, const Vec3& p0,
                                             const Vec3& p1, const Vec3& p2);

}  // namespace ray
