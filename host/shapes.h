// Exact ray intersection of the unit primitives in object space (SPEC §2), with their
// outward normals and texture coordinates (SPEC §5).
//
// The ray is origin + t·direction with any non-zero direction: the renderer passes a
// world ray transformed into object space, whose direction is not unit length, so that t
// is the same parameter in both spaces. Every routine returns the nearest hit with
// tMin < t < tMax, whether the ray starts outside the shape or inside it.
#pragma once

#include <optional>

#include "math.h"
#include "scene.h"

namespace ray {

// Texture coordinates, SPEC §5: u to the right and v up as seen from outside, in [0, 1].
struct UV {
    double u = 0, v = 0;
};

struct ShapeHit {
    double t = 0;
    Vec3 normal;  // object space, unit length, pointing out of the solid
    UV uv;
};

std::optional<ShapeHit> intersectCube(const Vec3& origin, const Vec3& direction, double tMin, double tMax);
std::optional<ShapeHit> intersectSphere(const Vec3& origin, const Vec3& direction, double tMin, double tMax);
std::optional<ShapeHit> intersectCylinder(const Vec3& origin, const Vec3& direction, double tMin, double tMax);
std::optional<ShapeHit> intersectCone(const Vec3& origin, const Vec3& direction, double tMin, double tMax);

// Dispatches on the type. Torus and mesh are not drawn yet: they return no hit (the
// renderer refuses scenes that contain them before it traces anything).
std::optional<ShapeHit> intersectUnitPrimitive(PrimitiveType type, const Vec3& origin, const Vec3& direction,
                                               double tMin, double tMax);

// The texture coordinates of SPEC §5, exposed for tests and for other renderers.
// The sphere's, also used around the sides of the cylinder and the cone.
double sphericalU(const Vec3& point);
// The cube's, chosen by the face's outward normal (±x, ±y or ±z).
UV cubeFaceUV(const Vec3& point, const Vec3& faceNormal);

}  // namespace ray
