// The numbers of the scene document and the elements the file writes them in (SPEC §1):
// one table for each kind of node, which the writers (canonical_writer.h, the canonical
// text; document_splices.h, the edits of a file's text) both read, so that a field's
// element and attribute names are said once for saving.
#pragma once

#include <array>

#include "scene/scene.h"

namespace ray {

// A field written as one element of three numbers: <diffuse r="" g="" b=""/>.
template <class Owner>
struct TripleField {
    const char* element;
    Vec3 Owner::*member;
    std::array<const char*, 3> attributes;
};

// A field written as one element of one number: <shininess v=""/>.
template <class Owner>
struct SingleField {
    const char* element;
    double Owner::*member;
};

inline constexpr std::array<const char*, 3> kXyz{"x", "y", "z"}, kRgb{"r", "g", "b"};

inline constexpr TripleField<Material> kMaterialTriples[] = {
    {"diffuse", &Material::diffuse, kRgb},         {"ambient", &Material::ambient, kRgb},
    {"specular", &Material::specular, kRgb},       {"reflective", &Material::reflective, kRgb},
    {"transparent", &Material::transparent, kRgb}, {"emissive", &Material::emissive, kRgb},
};
inline constexpr SingleField<Material> kMaterialSingles[] = {
    {"shininess", &Material::shininess}, {"ior", &Material::ior}, {"blend", &Material::blend}};

inline constexpr SingleField<GlobalCoefficients> kGlobalsSingles[] = {
    {"ambientcoeff", &GlobalCoefficients::ka},
    {"diffusecoeff", &GlobalCoefficients::kd},
    {"specularcoeff", &GlobalCoefficients::ks},
    {"transparentcoeff", &GlobalCoefficients::kt},
};

// <look> is the camera's direction; a file may give a <focus> point instead (the
// writers keep whichever the file wrote).
inline constexpr TripleField<Camera> kCameraTriples[] = {
    {"pos", &Camera::position, kXyz}, {"look", &Camera::look, kXyz}, {"up", &Camera::up, kXyz}};
inline constexpr SingleField<Camera> kCameraSingles[] = {{"heightangle", &Camera::heightAngleDegrees},
                                                         {"aperture", &Camera::aperture},
                                                         {"focallength", &Camera::focalLength}};

// The light's type is <type v="point"/> (lightTypeName), its index <id v=""/>.
inline constexpr TripleField<Light> kLightTriples[] = {
    {"color", &Light::color, kRgb},
    {"function", &Light::attenuation, {"v1", "v2", "v3"}},
    {"position", &Light::position, kXyz},
    {"direction", &Light::direction, kXyz},
};
inline constexpr SingleField<Light> kLightSingles[] = {
    {"angle", &Light::angleDegrees}, {"penumbra", &Light::penumbraDegrees}, {"radius", &Light::radius},
    {"width", &Light::width},        {"height", &Light::height},
};

}  // namespace ray
