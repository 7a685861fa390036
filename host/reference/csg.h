// Constructive solid geometry for the reference renderer (scene/csg.h), in double precision.
//
// Along a ray the solid of each operand is a list of spans, the stretches of the whole line
// (negative t too, so a ray starting inside an operand is handled like any other) between
// entering and leaving its surface. The program combines the lists by its operations; the
// combined solid's surface is where its spans begin and end. cl/geometry/csg.cl does the same in float.
#pragma once

#include <optional>
#include <vector>

#include "core/math.h"
#include "reference/shapes.h"
#include "scene/scene.h"

namespace ray {

// Where the ray crosses an operand's surface: the operand (index into Scene::csgOperands),
// its own hit there (t, outward object-space normal, texture coordinates) and whether the
// ray enters the operand there.
struct CsgBoundary {
    int operand = -1;
    bool entersOperand = true;
    ShapeHit hit;
};

// The ray is inside from enter.hit.t to exit.hit.t.
struct CsgSpan {
    CsgBoundary enter, exit;
};

// Disjoint spans in increasing t, none of zero length.
using CsgSpans = std::vector<CsgSpan>;

// The spans of a and b combined by a Union, Intersection or Difference step. Boundaries at
// exactly the same t are taken together (coincident faces, touching operands: a union of
// two touching solids has no surface between them); a boundary of the result on both
// operands' surfaces is b's (the operand written later, as SPEC §4 settles coincident
// surfaces).
CsgSpans combineCsgSpans(CsgStepKind kind, const CsgSpans& a, const CsgSpans& b);

// The span of one convex operand along origin + t·direction (world space), empty when the
// line misses it or only grazes it.
CsgSpans csgOperandSpans(const Scene& scene, int operand, const Vec3& origin, const Vec3& direction);

// The program's spans (every operand evaluated, the stack bounded by kCsgMaxStack).
CsgSpans evaluateCsg(const Scene& scene, const CsgObject& object, const Vec3& origin, const Vec3& direction);

struct CsgHit {
    int operand = -1;  // whose surface it is: its material, transform and texture coordinates
    ShapeHit local;    // in the operand's object space, the normal facing out of the combined solid
};

// The nearest surface of the combined solid with tMin < t < tMax.
std::optional<CsgHit> intersectCsg(const Scene& scene, const CsgObject& object, const Vec3& origin,
                                   const Vec3& direction, double tMin, double tMax);

}  // namespace ray
