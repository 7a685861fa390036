// The numbers of the scene document and the elements the file writes them in (SPEC §1):
// one table for each kind of node, which the writers (canonical_writer.h, the canonical
// text; document_splices.h, the edits of a file's text) both read, so that a field's
// element and attribute names are said once for saving. Each entry also says what values
// the field takes (its rule, scene/parameter_rules.h) and what it means (a help phrase),
// so that the editor's table of editable fields (edit/field_table.h), and through it the
// viewer's page, the C++ API and the Python module, read the same entry.
#pragma once

#include <array>

#include "scene/parameter_rules.h"
#include "scene/scene.h"

namespace ray {

// A field written as one element of three numbers: <diffuse r="" g="" b=""/>.
// `lights`: for a light's field, the light types that use it (lightTypeBit); others: all.
template <class Owner>
struct TripleField {
    const char* element;
    Vec3 Owner::*member;
    std::array<const char*, 3> attributes;
    const NumberRule* rule;  // each of the three numbers
    const char* help;
    unsigned lights = ~0u;
    bool nonzero = false;  // a direction: (0, 0, 0) is refused
};

// A field written as one element of one number: <shininess v=""/>.
template <class Owner>
struct SingleField {
    const char* element;
    double Owner::*member;
    const NumberRule* rule;
    const char* help;
    unsigned lights = ~0u;
};

// The bit of a light type in TripleField::lights and SingleField::lights.
constexpr unsigned lightTypeBit(LightType type) { return 1u << unsigned(type); }
inline constexpr unsigned kPositionedLights =
    lightTypeBit(LightType::Point) | lightTypeBit(LightType::Spot) | lightTypeBit(LightType::Area);
inline constexpr unsigned kAimedLights =
    lightTypeBit(LightType::Directional) | lightTypeBit(LightType::Spot) | lightTypeBit(LightType::Area);

inline constexpr std::array<const char*, 3> kXyz{"x", "y", "z"}, kRgb{"r", "g", "b"};

inline constexpr TripleField<Material> kMaterialTriples[] = {
    {"diffuse", &Material::diffuse, kRgb, &rules::kColorChannel, "the diffuse color Od, weighted by kd"},
    {"ambient", &Material::ambient, kRgb, &rules::kColorChannel, "the ambient color Oa, weighted by ka"},
    {"specular", &Material::specular, kRgb, &rules::kColorChannel, "the specular color Os, weighted by ks"},
    {"reflective", &Material::reflective, kRgb, &rules::kColorChannel,
     "the reflected color Or: how much of the mirror direction's light it returns"},
    {"transparent", &Material::transparent, kRgb, &rules::kColorChannel,
     "the transparent color Ot: how much light passes through, weighted by kt"},
    {"emissive", &Material::emissive, kRgb, &rules::kColorChannel, "the light the surface gives off itself"},
};
inline constexpr SingleField<Material> kMaterialSingles[] = {
    {"shininess", &Material::shininess, &rules::kShininess, "the specular exponent n of max(R·V, 0)^n"},
    {"ior", &Material::ior, &rules::kIor, "the index of refraction: 1 for air, 1.5 for glass"},
    {"blend", &Material::blend, &rules::kBlend, "the texture's weight against the diffuse color, 0 to 1"},
};

inline constexpr SingleField<GlobalCoefficients> kGlobalsSingles[] = {
    {"ambientcoeff", &GlobalCoefficients::ka, &rules::kFinite, "ka, the weight of every ambient color"},
    {"diffusecoeff", &GlobalCoefficients::kd, &rules::kFinite, "kd, the weight of every diffuse color"},
    {"specularcoeff", &GlobalCoefficients::ks, &rules::kFinite,
     "ks, the weight of every specular color and of reflections"},
    {"transparentcoeff", &GlobalCoefficients::kt, &rules::kFinite, "kt, the weight of every transparent color"},
};

// <look> is the camera's direction; a file may give a <focus> point instead (the
// writers keep whichever the file wrote).
inline constexpr TripleField<Camera> kCameraTriples[] = {
    {"pos", &Camera::position, kXyz, &rules::kFinite, "where the eye is"},
    {"look", &Camera::look, kXyz, &rules::kFinite, "the direction the camera looks in", ~0u, true},
    {"up", &Camera::up, kXyz, &rules::kFinite, "the direction that is up in the image", ~0u, true}};
inline constexpr SingleField<Camera> kCameraSingles[] = {
    {"heightangle", &Camera::heightAngleDegrees, &rules::kHeightAngle,
     "the full vertical field of view, in degrees"},
    {"aperture", &Camera::aperture, &rules::kFinite, "the lens's diameter; 0 is a pinhole"},
    {"focallength", &Camera::focalLength, &rules::kFinite, "the distance in focus, with an aperture"}};

// The light's type is <type v="point"/> (lightTypeName), its index <id v=""/>.
inline constexpr TripleField<Light> kLightTriples[] = {
    {"color", &Light::color, kRgb, &rules::kColorChannel, "the light's color and intensity"},
    {"function", &Light::attenuation, {"v1", "v2", "v3"}, &rules::kAttenuation,
     "c1, c2, c3 of the attenuation 1/(c1 + c2·d + c3·d²)", kPositionedLights},
    {"position", &Light::position, kXyz, &rules::kFinite, "where the light is (an area light's centre)",
     kPositionedLights},
    {"direction", &Light::direction, kXyz, &rules::kFinite, "the direction the light shines in", kAimedLights,
     true},
};
inline constexpr SingleField<Light> kLightSingles[] = {
    {"angle", &Light::angleDegrees, &rules::kSpotAngle, "the half-angle of the spot light's cone, in degrees",
     lightTypeBit(LightType::Spot)},
    {"penumbra", &Light::penumbraDegrees, &rules::kPenumbra,
     "the width in degrees of the soft band inside the cone", lightTypeBit(LightType::Spot)},
    {"radius", &Light::radius, &rules::kSpotRadius, "the spot light's radius (read and kept; not rendered)",
     lightTypeBit(LightType::Spot)},
    {"width", &Light::width, &rules::kAreaSide, "the area light's width", lightTypeBit(LightType::Area)},
    {"height", &Light::height, &rules::kAreaSide, "the area light's height", lightTypeBit(LightType::Area)},
};

}  // namespace ray
