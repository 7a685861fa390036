#include "scene/parameter_rules.h"

#include <cmath>
#include <cstdint>
#include <sstream>

namespace ray {

namespace {

bool keeps(double value, const NumberRule& rule) {
    const bool aboveLow = rule.lowIncluded ? value >= rule.low : value > rule.low;
    const bool belowHigh = rule.highIncluded ? value <= rule.high : value < rule.high;
    return std::isfinite(value) && aboveLow && belowHigh;
}

// "0 or more", "more than 0", "between 0 and 1", "more than 0 and at most 180", ...
// (Streams rather than "literal" + std::string, on which GCC 12 warns falsely, -Wrestrict.)
std::string interval(const NumberRule& rule) {
    std::ostringstream out;
    if (std::isinf(rule.low) && std::isinf(rule.high)) {
        out << "a finite number";
    } else if (std::isinf(rule.high)) {
        if (rule.lowIncluded) out << rule.low << " or more";
        else out << "more than " << rule.low;
    } else if (rule.lowIncluded && rule.highIncluded) {
        out << "between " << rule.low << " and " << rule.high;
    } else {
        out << (rule.lowIncluded ? "at least " : "more than ") << rule.low
            << (rule.highIncluded ? " and at most " : " and less than ") << rule.high;
    }
    return out.str();
}

template <class Value>
RuleBroken broken(std::string_view name, const std::string& must, const Value& value, const NumberRule& rule) {
    std::ostringstream problem;
    problem << name << " must be " << must << ", not " << value;
    return {problem.str(), std::string(rule.meaning)};
}

struct Triple {
    const Vec3& value;
};
std::ostream& operator<<(std::ostream& out, Triple t) {
    return out << "(" << t.value.x << ", " << t.value.y << ", " << t.value.z << ")";
}

}  // namespace

std::optional<RuleBroken> brokenRule(std::string_view name, double value, const NumberRule& rule) {
    if (keeps(value, rule)) return std::nullopt;
    return broken(name, interval(rule), value, rule);
}

std::optional<RuleBroken> brokenRule(std::string_view name, const Vec3& value, const NumberRule& rule) {
    if (keeps(value.x, rule) && keeps(value.y, rule) && keeps(value.z, rule)) return std::nullopt;
    return broken(name, interval(rule) + " in each component", Triple{value}, rule);
}

std::optional<RuleBroken> brokenCameraAxes(const Camera& camera, std::string_view lookName, std::string_view upName) {
    if (!(length(camera.look) > 0))
        return RuleBroken{"the camera looks nowhere (its look direction is zero)", std::string("give a non-zero ").append(lookName)};
    if (!(length(cross(camera.look, camera.up)) > 1e-12 * length(camera.look) * length(camera.up)))
        return RuleBroken{"the camera's up vector is zero or parallel to its look direction",
                          std::string("give an ").append(upName).append(" that points away from the look direction")};
    return std::nullopt;
}

std::string formatNumber(double value) {
    std::ostringstream out;
    // Whole numbers in full (4294967295, not 4.29497e+09); others as the stream writes them.
    if (value == std::floor(value) && std::fabs(value) < 1e15)
        out << int64_t(value);
    else
        out << value;
    return out.str();
}

}  // namespace ray
