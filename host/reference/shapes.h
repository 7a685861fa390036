// Exact ray intersection of the unit primitives in object space (SPEC §2), with their
// outward normals and texture coordinates (SPEC §5).
//
// The ray is origin + t·direction with any non-zero direction: the renderer passes a
// world ray transformed into object space, whose direction is not unit length, so that t
// is the same parameter in both spaces. Every routine returns the nearest hit with
// tMin < t < tMax, whether the ray starts outside the shape or inside it.
#pragma once

#include <optional>

#include "core/math.h"
#include "scene/scene.h"
#include "shared_types.h"

namespace ray {

// Texture coordinates, SPEC §5: u to the right and v up as seen from outside, in [0, 1].
struct UV {
    double u = 0, v = 0;
};

struct ShapeHit {
    double t = 0;
    Vec3 normal;  // object space, unit length, pointing out of the solid
    UV uv;
    Vec3 tangent;  // meshes: object-space direction of increasing u (bump mapping); zero: none
    // meshes: +1, or −1 where the texture coordinates are mirrored about the shading normal
    // (bump mapping's B = bitangentSign · (N × T)); every other shape +1
    double bitangentSign = 1;
};

std::optional<ShapeHit> intersectCube(const Vec3& origin, const Vec3& direction, double tMin, double tMax);
std::optional<ShapeHit> intersectSphere(const Vec3& origin, const Vec3& direction, double tMin, double tMax);
std::optional<ShapeHit> intersectCylinder(const Vec3& origin, const Vec3& direction, double tMin, double tMax);
std::optional<ShapeHit> intersectCone(const Vec3& origin, const Vec3& direction, double tMin, double tMax);
// The torus of SPEC §2: the ring of major radius kTorusMajorRadius around the y axis, in
// the xz plane, swept by a circle of radius kTorusMinorRadius (cl/shared_types.h, shared
// with the kernel and the scene's bounds). Normal from the nearest
// point of the ring; u as the sphere's around y, v = the angle around the tube / 2π,
// measured from the outer equator and growing upward on the outside (v up as seen from
// outside, as SPEC §5 asks of every mapping).
constexpr double kTorusMajorRadius = RAY_TORUS_MAJOR_RADIUS, kTorusMinorRadius = RAY_TORUS_MINOR_RADIUS;
std::optional<ShapeHit> intersectTorus(const Vec3& origin, const Vec3& direction, double tMin, double tMax);

// Dispatches on the type. Meshes are not unit primitives: they return no hit here (the
// reference BVH intersects them with their own mesh intersector).
std::optional<ShapeHit> intersectUnitPrimitive(PrimitiveType type, const Vec3& origin, const Vec3& direction,
                                               double tMin, double tMax);

// The texture coordinates of SPEC §5, exposed for tests and for other renderers.
// The sphere's, also used around the sides of the cylinder and the cone.
double sphericalU(const Vec3& point);
// The cube's, chosen by the face's outward normal (±x, ±y or ±z).
UV cubeFaceUV(const Vec3& point, const Vec3& faceNormal);

}  // namespace ray
