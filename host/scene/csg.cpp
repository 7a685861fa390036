#include "scene/csg.h"

#include <algorithm>

namespace ray {

int csgStackDepth(const CsgObject& object) {
    int depth = 0, deepest = 0;
    for (const CsgStep& step : object.program) {
        depth += step.kind == CsgStepKind::Operand ? 1 : -1;
        deepest = std::max(deepest, depth);
    }
    return deepest;
}

void csgBounds(const CsgObject& object, const std::vector<Vec3>& operandLo, const std::vector<Vec3>& operandHi,
               Vec3& lo, Vec3& hi) {
    struct Box {
        Vec3 lo, hi;
    };
    std::vector<Box> stack;
    for (const CsgStep& step : object.program) {
        if (step.kind == CsgStepKind::Operand) {
            stack.push_back({operandLo[size_t(step.operand)], operandHi[size_t(step.operand)]});
            continue;
        }
        Box b = stack.back();
        stack.pop_back();
        Box& a = stack.back();
        if (step.kind == CsgStepKind::Union) {
            a.lo = componentMin(a.lo, b.lo);
            a.hi = componentMax(a.hi, b.hi);
        } else if (step.kind == CsgStepKind::Intersection) {
            a.lo = componentMax(a.lo, b.lo);
            a.hi = componentMin(a.hi, b.hi);
            // An empty intersection keeps a point-sized box (a box with lo > hi would
            // turn inside out through the corner transform of the BVHs).
            a.hi = componentMax(a.hi, a.lo);
        }
    }
    lo = stack.back().lo;
    hi = stack.back().hi;
}

}  // namespace ray
