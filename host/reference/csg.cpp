#include "reference/csg.h"

#include <cmath>
#include <stdexcept>

namespace ray {

namespace {

// The boundaries of a span list in order: even positions enter, odd ones leave.
const CsgBoundary& boundaryAt(const CsgSpans& spans, size_t i) {
    return i % 2 == 0 ? spans[i / 2].enter : spans[i / 2].exit;
}

double boundaryT(const CsgSpans& spans, size_t i) {
    return i < 2 * spans.size() ? boundaryAt(spans, i).hit.t : INFINITY;
}

}  // namespace

CsgSpans combineCsgSpans(CsgStepKind kind, const CsgSpans& a, const CsgSpans& b) {
    CsgSpans result;
    const size_t endA = 2 * a.size(), endB = 2 * b.size();
    size_t i = 0, j = 0;  // boundaries of a and b passed so far; odd: inside
    bool inside = csgCombine(kind, false, false);
    while (i < endA || j < endB) {
        const double t = std::min(boundaryT(a, i), boundaryT(b, j));
        const CsgBoundary* crossed = nullptr;
        if (i < endA && boundaryT(a, i) == t) crossed = &boundaryAt(a, i++);
        // A boundary on both surfaces is b's, the operand written later (SPEC §4,
        // coincident surfaces).
        if (j < endB && boundaryT(b, j) == t) crossed = &boundaryAt(b, j++);
        const bool now = csgCombine(kind, i % 2 == 1, j % 2 == 1);
        if (now == inside) continue;
        inside = now;
        if (now && !result.empty() && csgSliver(result.back().exit.hit.t, t))
            continue;  // a sliver of a gap: the previous span goes on
        if (now) result.push_back({*crossed, *crossed});
        else if (csgSliver(result.back().enter.hit.t, t)) result.pop_back();  // a sliver of a span
        else result.back().exit = *crossed;
    }
    return result;
}

CsgSpans csgOperandSpans(const Scene& scene, int operand, const Vec3& origin, const Vec3& direction) {
    const PrimitiveInstance& instance = scene.csgOperands[size_t(operand)];
    const Vec3 o = instance.worldToObject.transformPoint(origin);
    const Vec3 d = instance.worldToObject.transformVector(direction);
    // A convex solid is entered at its nearest surface point along the whole line and left
    // at the farthest, which is the nearest one seen along the reversed line.
    auto enter = intersectUnitPrimitive(instance.type, o, d, -INFINITY, INFINITY);
    auto exit = intersectUnitPrimitive(instance.type, o, -1 * d, -INFINITY, INFINITY);
    if (!enter || !exit) return {};
    exit->t = -exit->t;
    // Grazing: no inside. Non-finite ends (overflowing transforms) are no span either: the
    // combination compares ends for equality, which a NaN would never satisfy.
    if (!(exit->t > enter->t) || !std::isfinite(enter->t) || !std::isfinite(exit->t)) return {};
    return {CsgSpan{{operand, true, *enter}, {operand, false, *exit}}};
}

CsgSpans evaluateCsg(const Scene& scene, const CsgObject& object, const Vec3& origin, const Vec3& direction) {
    std::vector<CsgSpans> stack;
    stack.reserve(kCsgMaxStack);
    for (const CsgStep& step : object.program) {
        if (step.kind == CsgStepKind::Operand) {
            stack.push_back(csgOperandSpans(scene, step.operand, origin, direction));
            continue;
        }
        if (stack.size() < 2) throw std::logic_error("a csg program pops an empty stack");
        CsgSpans b = std::move(stack.back());
        stack.pop_back();
        stack.back() = combineCsgSpans(step.kind, stack.back(), b);
    }
    return stack.empty() ? CsgSpans{} : std::move(stack.back());
}

std::optional<CsgHit> intersectCsg(const Scene& scene, const CsgObject& object, const Vec3& origin,
                                   const Vec3& direction, double tMin, double tMax) {
    for (const CsgSpan& span : evaluateCsg(scene, object, origin, direction)) {
        for (const CsgBoundary* boundary : {&span.enter, &span.exit}) {
            const double t = boundary->hit.t;
            if (t >= tMax) return std::nullopt;
            if (t <= tMin) continue;
            CsgHit hit{boundary->operand, boundary->hit};
            // The operand's outward normal faces out of the result where the ray enters
            // both or leaves both; where a subtracted operand is entered the result is
            // left (and the other way round), so its normal turns around.
            const bool entersResult = boundary == &span.enter;
            if (entersResult != boundary->entersOperand) hit.local.normal = -1 * hit.local.normal;
            return hit;
        }
    }
    return std::nullopt;
}

}  // namespace ray
