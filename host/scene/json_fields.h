// The keys of the course's JSON scenefiles (SPEC §7) that hold the scene document's numbers,
// each with the field of scene/document_fields.h it holds, named by that field's XML element
// (document_fields.h says a field's member, rule and help once; this says its JSON key once).
// Each table is in the order the course's files write the keys, which is the order the JSON
// writer (json_writer.h) writes them in. A field of document_fields.h with no entry here has
// no JSON key (emissive; a light's position, which its group's translate gives; a spot
// light's radius; an area light's width and height).
#pragma once

namespace ray {

struct JsonKey {
    const char* key;      // as the JSON writes it: "attenuationCoeff"
    const char* element;  // the field's XML element in document_fields.h: "function"
};

inline constexpr JsonKey kJsonGlobalsKeys[] = {
    {"ambientCoeff", "ambientcoeff"},
    {"diffuseCoeff", "diffusecoeff"},
    {"specularCoeff", "specularcoeff"},
    {"transparentCoeff", "transparentcoeff"},
};

// The camera's direction is "look" (a JSON file may give a "focus" point instead, which the
// reader turns into a look direction).
inline constexpr JsonKey kJsonCameraKeys[] = {
    {"position", "pos"},     {"up", "up"},           {"heightAngle", "heightangle"},
    {"look", "look"},        {"aperture", "aperture"}, {"focalLength", "focallength"},
};

// A light's "type" comes first, then these that its type uses (document_fields.h's
// TripleField::lights and SingleField::lights say which).
inline constexpr JsonKey kJsonLightKeys[] = {
    {"color", "color"},     {"direction", "direction"},        {"angle", "angle"},
    {"penumbra", "penumbra"}, {"attenuationCoeff", "function"},
};

// A primitive's "type" and (a mesh's) "meshFile" come first, then these, then its texture
// ("textureFile", "textureU", "textureV") and bump map ("bumpMapFile", "bumpMapU",
// "bumpMapV").
inline constexpr JsonKey kJsonMaterialKeys[] = {
    {"ambient", "ambient"},         {"diffuse", "diffuse"},         {"specular", "specular"},
    {"shininess", "shininess"},     {"reflective", "reflective"},   {"transparent", "transparent"},
    {"ior", "ior"},                 {"blend", "blend"},
};

}  // namespace ray
