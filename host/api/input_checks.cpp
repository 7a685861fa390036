#include "api/input_checks.h"

#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "api/camera_conversion.h"
#include "api/settings_conversion.h"
#include "render/render_settings.h"
#include "scene/parameter_rules.h"

namespace ray::api::detail {

namespace {

[[noreturn]] void badInput(const std::string& what) { throw InputError("error: " + what, "", 0); }

template <class Value>
void checkRule(std::string_view name, const Value& value, const NumberRule& rule) {
    if (std::optional<RuleBroken> broken = brokenRule(name, value, rule)) badInput(broken->sentence());
}

}  // namespace

void checkFinite(const char* name, const Vec3& values) { checkRule(name, toInternal(values), rules::kFinite); }
void checkFinite(const char* name, double value) { checkRule(name, value, rules::kFinite); }

// The conversion checks each value against the table as it goes.
void checkSettings(const Settings& s) { toInternal(s); }

}  // namespace ray::api::detail
