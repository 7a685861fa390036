// The values a scene's numeric parameters may take: one place for every way into a scene,
// the scenefile loader (scene_loader.cpp, which reports the element's line) and the public
// API (host/api/scene.cpp: Scene::addMaterial, addLight, setCamera; the Python module).
//
// The rules refuse only what has no meaning in SPEC §4's lighting model (a negative
// exponent, an index of refraction of 0, a blend beyond 1, a cone wider than all
// directions): colors may exceed 1 (course scenes use diffuse 80), and a penumbra may be
// wider than its cone (spotlight_on_cheese.xml), which the renderers handle.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "core/math.h"
#include "scene/scene.h"

namespace ray {

// What a number must be: an interval, each end included or not, and what the number means,
// for the message's "what to do".
struct NumberRule {
    double low = -std::numeric_limits<double>::infinity();
    bool lowIncluded = true;
    double high = std::numeric_limits<double>::infinity();
    bool highIncluded = true;
    const char* meaning = "";
};

namespace rules {
constexpr double kUnbounded = std::numeric_limits<double>::infinity();
inline constexpr NumberRule kColorChannel{0, true, kUnbounded, true,
                                          "each channel is linear, 0 for none and 1 for full (brighter is allowed)"};
inline constexpr NumberRule kShininess{0, true, kUnbounded, true, "it is the specular exponent n of max(R·V, 0)^n"};
inline constexpr NumberRule kIor{0, false, kUnbounded, true, "it is an index of refraction: 1 for air, 1.5 for glass"};
inline constexpr NumberRule kBlend{0, true, 1, true, "it is the texture's weight against the diffuse color"};
inline constexpr NumberRule kAttenuation{0, true, kUnbounded, true,
                                         "they are c1, c2, c3 of the attenuation 1/(c1 + c2·d + c3·d²)"};
inline constexpr NumberRule kSpotAngle{0, false, 180, true, "it is the half-angle of the spot light's cone, in degrees"};
inline constexpr NumberRule kPenumbra{0, true, kUnbounded, true,
                                      "it is the width in degrees of the soft band inside the spot light's cone"};
inline constexpr NumberRule kSpotRadius{0, true, kUnbounded, true, "it is the spot light's radius"};
inline constexpr NumberRule kAreaSide{0, false, kUnbounded, true, "it is a side of the area light's rectangle"};
// A point, a direction or a global coefficient: any finite number (the loader reads no other).
inline constexpr NumberRule kFinite{-kUnbounded, true, kUnbounded, true,
                                    "a scenefile holds finite decimal numbers only"};
inline constexpr NumberRule kHeightAngle{0, false, 180, false,
                                         "it is the camera's full vertical field of view, in degrees"};
}  // namespace rules

// What is wrong with a value, and what to do: the two halves of a loader error.
struct RuleBroken {
    std::string problem;  // "shininess must be 0 or more, not -5"
    std::string remedy;   // "it is the specular exponent ...; give a value in range"
    std::string sentence() const { return problem + "; " + remedy; }
};

// Nothing when `value` keeps the rule; else what is wrong, naming the parameter `name`.
// NaN and infinities break every rule.
std::optional<RuleBroken> brokenRule(std::string_view name, double value, const NumberRule& rule);
// The same for each component of a triple (a color, the attenuation coefficients).
std::optional<RuleBroken> brokenRule(std::string_view name, const Vec3& value, const NumberRule& rule);

// Nothing when the camera's look direction is non-zero and its up vector is neither zero
// nor parallel to it; else what is wrong, naming the two as the caller calls them.
std::optional<RuleBroken> brokenCameraAxes(const Camera& camera, std::string_view lookName, std::string_view upName);

// A number as people write it: 16384, 4294967295, 0.5, 1e-06 (not std::to_string's
// "16384.000000"). The loader's, the settings table's and the command line's messages use it.
std::string formatNumber(double value);

}  // namespace ray
