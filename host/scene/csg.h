// Constructive solid geometry in the flattened scene (our extension of the format):
// <object type="csg" operation="union|intersection|difference"> with two or more operands.
//
// A csg object is kept as a postfix program over its operand instances: an Operand step
// pushes the solid of one primitive instance (Scene::csgOperands), an operator step pops
// two solids and pushes their combination. An operand written as a transblock with several
// primitives is their union; a nested csg object is its own sub-program; "difference"
// subtracts every later operand from the first (a b − c − …). Both renderers evaluate the
// program on the intervals along a ray inside each operand (host/reference/csg.h,
// cl/geometry/csg.cl), with a stack bounded by kCsgMaxStack and intervals bounded by kCsgMaxOperands:
// every operand is convex (one interval), and combining lists of m and n intervals gives at
// most m + n, so an object of at most kCsgMaxOperands operands never overflows.
#pragma once

#include <vector>

#include "core/math.h"

namespace ray {

enum class CsgStepKind { Operand, Union, Intersection, Difference };

struct CsgStep {
    CsgStepKind kind = CsgStepKind::Operand;
    int operand = -1;  // Operand steps: index into Scene::csgOperands
};

struct CsgObject {
    std::vector<CsgStep> program;  // postfix
};

// The limits both renderers size their fixed arrays by (equal to cl/shared_types.h's
// RAY_CSG_MAX_OPERANDS and RAY_CSG_MAX_STACK); the loader refuses objects beyond them.
constexpr int kCsgMaxOperands = 32;
constexpr int kCsgMaxStack = 4;

// Spans and gaps thinner than this fraction of their distance along the ray are slivers of
// rounding, not geometry: where two operands share a face (a cube cut by a box flush with
// its front), their two planes are computed through different transforms and land a few
// ulps apart, leaving a film that shadow rays would hit (speckle in float). Both renderers
// drop such spans and close such gaps at every combination (equal to cl/geometry/csg.cl's
// RAY_CSG_SLIVER). 1e-5 is about 100 float ulps of the distance, and invisibly thin.
constexpr double kCsgSliver = 1e-5;

// Whether the stretch from t0 to t1 (t0 <= t1) is a sliver.
inline bool csgSliver(double t0, double t1) {
    double reach = t0 < 0 ? -t0 : t0;
    if (t1 > reach) reach = t1;
    if (-t1 > reach) reach = -t1;
    return t1 - t0 <= kCsgSliver * reach;
}

// How deep the program's evaluation stack gets.
int csgStackDepth(const CsgObject& object);

// The boolean operation on "inside" states.
inline bool csgCombine(CsgStepKind kind, bool insideA, bool insideB) {
    switch (kind) {
        case CsgStepKind::Union: return insideA || insideB;
        case CsgStepKind::Intersection: return insideA && insideB;
        case CsgStepKind::Difference: return insideA && !insideB;
        case CsgStepKind::Operand: break;
    }
    return false;
}

// A box that holds the combined solid, from the operands' boxes (lo/hi per operand):
// union grows, intersection clips, difference keeps the first operand's box.
void csgBounds(const CsgObject& object, const std::vector<Vec3>& operandLo, const std::vector<Vec3>& operandHi,
               Vec3& lo, Vec3& hi);

}  // namespace ray
