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

void checkMaterial(const Material& m) {
    for (const auto& [name, color] : {std::pair{"diffuse", m.diffuse}, {"ambient", m.ambient}, {"specular", m.specular},
                                      {"reflective", m.reflective}, {"transparent", m.transparent},
                                      {"emissive", m.emissive}})
        checkRule(name, toInternal(color), rules::kColorChannel);
    checkRule("shininess", m.shininess, rules::kShininess);
    checkRule("ior", m.ior, rules::kIor);
    checkRule("blend", m.blend, rules::kBlend);
}

void checkLight(const Light& light) {
    checkRule("color", toInternal(light.color), rules::kColorChannel);
    checkRule("attenuation", toInternal(light.attenuation), rules::kAttenuation);
    checkRule("angle", light.angleDegrees, rules::kSpotAngle);
    checkRule("penumbra", light.penumbraDegrees, rules::kPenumbra);
    checkRule("width", light.width, rules::kAreaSide);
    checkRule("height", light.height, rules::kAreaSide);
}

void checkCamera(const ray::Camera& camera) {
    checkRule("height angle", camera.heightAngleDegrees, rules::kHeightAngle);
    if (std::optional<RuleBroken> broken = brokenCameraAxes(camera, "look direction", "up vector"))
        badInput(broken->sentence());
}

// The conversion checks each value against the table as it goes.
void checkSettings(const Settings& s) { toInternal(s); }

}  // namespace ray::api::detail
