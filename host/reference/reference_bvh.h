// Finding what a ray hits in a flattened scene, for the reference renderer.
//
// A plain bounding volume hierarchy over the primitive instances' world-space boxes:
// split at the median of the box centres along their longest axis until at most a few
// primitives remain. It is not tuned (the kernel has its own SAH tree); it is there
// because the course's scenes reach millions of instances. A brute-force mode tests
// every primitive instead, so a test can check that the tree changes nothing.
#pragma once

#include <optional>
#include <vector>

#include "core/math.h"
#include "scene/scene.h"
#include "reference/mesh_intersector.h"
#include "reference/shapes.h"

// In a namespace of their own: the kernel's BVH (bvh.h) has similar names.
namespace ray::reference {

// An axis-aligned box; the default one is empty (lo > hi).
struct Aabb {
    Vec3 lo{INFINITY, INFINITY, INFINITY};
    Vec3 hi{-INFINITY, -INFINITY, -INFINITY};

    void grow(const Vec3& p) {
        lo = componentMin(lo, p);
        hi = componentMax(hi, p);
    }
    void grow(const Aabb& b) {
        lo = componentMin(lo, b.lo);
        hi = componentMax(hi, b.hi);
    }
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3 centre() const { return (lo + hi) * 0.5; }
    int longestAxis() const;
};

// The world-space box of an instance: the box around the eight transformed corners of its
// object-space box (PrimitiveInstance::objectLo/objectHi: the unit cube for most). A
// moving instance's box covers its whole motion: the union of its boxes at t = 0 and t = 1
// (a translation sweeps the box linearly, so the two ends bound every time between).
Aabb worldBounds(const PrimitiveInstance& instance);

// Where the entering ray meets the box within [tMin, tMax], or nothing.
std::optional<double> intersectBox(const Aabb& box, const Vec3& origin, const Vec3& direction, double tMin,
                                   double tMax);

struct SceneHit {
    int primitive = -1;  // index into Scene::primitives
    ShapeHit local;      // t, object-space normal, texture coordinates
    int csgOperand = -1;  // a csg object's hit: the operand (Scene::csgOperands) whose surface it is
};

// The instance whose surface was hit: the primitive, or for a csg object the operand
// (its transform, material and type; local is in its object space).
inline const PrimitiveInstance& surfaceInstance(const Scene& scene, const SceneHit& hit) {
    return hit.csgOperand >= 0 ? scene.csgOperands[size_t(hit.csgOperand)] : scene.primitives[size_t(hit.primitive)];
}

enum class SceneSearch { Bvh, BruteForce };

class SceneIntersector {
public:
    // Keeps a reference to scene.primitives: the scene must outlive the intersector.
    //
    // courseMeshes (--course-meshes, docs/conventions.md, meshes): closestHit measures a
    // mesh instance's hit by the course's key t_obj = t·|M⁻¹d|/|d| (the distance along the
    // normalized object-space direction, M the object-to-world transform), compares it
    // with the other primitives' world t, returns it as the hit's t (so the hit point is
    // origin + t_obj·d) and gives meshes their face normals. anyHit (shadow rays) keeps
    // world t for every primitive.
    explicit SceneIntersector(const Scene& scene, SceneSearch search = SceneSearch::Bvh, bool courseMeshes = false);

    // The nearest hit with tMin < t < tMax along origin + t·direction (world space), with
    // the moving instances where they are at shutter time `time` (scene.h).
    std::optional<SceneHit> closestHit(const Vec3& origin, const Vec3& direction, double tMin, double tMax,
                                       double time = 0) const;
    // Whether anything lies along the ray with tMin < t < tMax (shadow rays).
    bool anyHit(const Vec3& origin, const Vec3& direction, double tMin, double tMax, double time = 0) const;

    // The box around every primitive (empty for an empty scene).
    const Aabb& sceneBounds() const { return sceneBounds_; }

private:
    struct Node {
        Aabb bounds;
        int first = 0, count = 0;  // a leaf: primitives order_[first, first + count)
        int left = -1, right = -1;  // an inner node (count == 0): its children
    };

    int build(int begin, int end, const std::vector<Aabb>& boxes, const std::vector<Vec3>& centres);
    std::optional<SceneHit> intersectPrimitive(int index, const Vec3& origin, const Vec3& direction, double tMin,
                                               double tMax, double time) const;
    // Calls test(primitive index) for every primitive whose box the ray reaches before
    // the current tMax; test returns the new tMax (smaller after a hit), or a negative
    // value to stop the search.
    // Boxes are tested against tMax·stretch: 1 except for closestHit with courseMeshes,
    // where a mesh's key can be smaller than its world t (meshKeyStretch_).
    template <class Test>
    void traverse(const Vec3& origin, const Vec3& direction, double tMin, double tMax, double stretch,
                  Test&& test) const;

    const Scene& scene_;
    const std::vector<PrimitiveInstance>& primitives_;
    std::vector<MeshIntersector> meshes_;  // one per Scene::meshes entry
    SceneSearch search_;
    bool courseMeshes_ = false;
    // With courseMeshes: an upper bound on world t / t_obj over the mesh instances (≥ 1),
    // the largest Frobenius norm of their transforms' linear parts (≥ its largest
    // singular value) times 1 + 1e-6 for rounding; 1 when there is no mesh. A box the ray
    // enters at t holds no mesh key below t / meshKeyStretch_, so pruning boxes by
    // tMax·meshKeyStretch_ is exact.
    double meshKeyStretch_ = 1;
    std::vector<Node> nodes_;  // nodes_[0] is the root
    std::vector<int> order_;   // primitive indices, grouped by leaf
    Aabb sceneBounds_;
};

}  // namespace ray::reference
