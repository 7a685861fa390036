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
    checkRule("position", toInternal(light.position), rules::kFinite);
    checkRule("direction", toInternal(light.direction), rules::kFinite);
    checkRule("color", toInternal(light.color), rules::kColorChannel);
    checkRule("attenuation", toInternal(light.attenuation), rules::kAttenuation);
    checkRule("angle", light.angleDegrees, rules::kSpotAngle);
    checkRule("penumbra", light.penumbraDegrees, rules::kPenumbra);
    checkRule("width", light.width, rules::kAreaSide);
    checkRule("height", light.height, rules::kAreaSide);
}

void checkCamera(const ray::Camera& camera) {
    checkRule("position", camera.position, rules::kFinite);
    checkRule("look direction", camera.look, rules::kFinite);
    checkRule("up vector", camera.up, rules::kFinite);
    checkRule("height angle", camera.heightAngleDegrees, rules::kHeightAngle);
    checkRule("aperture", camera.aperture, rules::kFinite);
    checkRule("focal length", camera.focalLength, rules::kFinite);
    if (std::optional<RuleBroken> broken = brokenCameraAxes(camera, "look direction", "up vector"))
        badInput(broken->sentence());
}

void checkGlobals(const Globals& globals) {
    for (const auto& [name, value] : {std::pair{"ka", globals.ka}, {"kd", globals.kd}, {"ks", globals.ks},
                                      {"kt", globals.kt}})
        checkRule(name, value, rules::kFinite);
}

void checkFinite(const char* name, const Vec3& values) { checkRule(name, toInternal(values), rules::kFinite); }
void checkFinite(const char* name, double value) { checkRule(name, value, rules::kFinite); }

// The conversion checks each value against the table as it goes.
void checkSettings(const Settings& s) { toInternal(s); }

}  // namespace ray::api::detail
