// The editable fields of a scene, declared once (field_table.cpp), as the render settings
// are (render/settings_table.h): each names the kind of node it belongs to, the scenefile's
// name for it, the kind of value it holds, the values it may take (scene/parameter_rules.h)
// and a help phrase. The numbers' entries are scene/document_fields.h's own (the table the
// saver writes them with); this adds the fields that are not one element of numbers: an
// object's texture and bump map, its transforms, a light's type, a tree's name.
//
// Everything that edits reads it: the editing service checks and sets values through it
// (edit_session.h), the viewer's page builds its properties panel from it (GET /fields),
// the C++ API converts its structs field by field through it, the Python module takes its
// keywords from it. Adding a field: one entry (here, or in document_fields.h for a number
// the file writes), and, if the value is not a member of a material, light, camera or the
// globals, its reading and writing in edit_session.cpp (SpecialField).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/math.h"
#include "scene/document_fields.h"
#include "scene/parameter_rules.h"
#include "scene/scene.h"
#include "scene/scene_document.h"

namespace ray::edit {

// The kind of node a field belongs to (edit/node_id.h): an object's material is its own.
enum class FieldOwner { Object, Light, Camera, Globals, Block, Tree };

// What a field holds (FieldValue's alternative, and its JSON, docs/modeler-protocol.md).
enum class FieldKind {
    Number,      // double
    Color,       // Vec3, each channel a number
    Vector,      // Vec3
    Choice,      // std::string, one of the entry's choices
    Text,        // std::string
    File,        // std::string: a file (or ImageHandle: an image made in code)
    Transforms,  // std::vector<TransformOp>
    Matrix,      // Affine
};

// Fields that are not a member of a Material, Light, Camera or GlobalCoefficients.
enum class SpecialField {
    None,
    Texture, TextureU, TextureV,  // <texture file="" u="" v=""/>
    BumpMap, BumpMapU, BumpMapV,  // <bumpmap file="" u="" v=""/>
    Transforms,                   // an object's own transblock's, or a transblock's
    World,                        // an object's object-to-world, at its first placement
    LightType,                    // <type v=""/>
    TreeName,                     // <object type="tree" name="">
};

using FieldMember = std::variant<std::monostate, Vec3 Material::*, double Material::*, Vec3 Light::*, double Light::*,
                                 Vec3 Camera::*, double Camera::*, double GlobalCoefficients::*>;

struct EditField {
    FieldOwner owner;
    std::string_view group;  // the panel's heading: "material", "texture", "transform", ...
    std::string_view name;   // the scenefile's: "diffuse", "texture.u" (an attribute of <texture>)
    FieldKind kind;
    std::string_view help;
    const NumberRule* rule = nullptr;  // Number, Color, Vector: each number's
    unsigned lights = ~0u;             // a light's field: the types using it (lightTypeBit)
    bool nonzero = false;              // a direction: (0, 0, 0) refused
    FieldMember member = {};
    SpecialField special = SpecialField::None;
    std::vector<std::string_view> choices = {};     // Choice
    std::vector<std::string_view> extensions = {};  // File
    size_t maxLength = 0;                           // Text

    // The name as a Python keyword and C++ identifier: "texture_u" for "texture.u".
    std::string keyword() const;
    bool appliesTo(LightType type) const { return (lights & lightTypeBit(type)) != 0; }
};

// Every editable field, in the order the panel shows them.
const std::vector<EditField>& editFields();
// The field of `owner` named `name` (the scenefile's name or its keyword); null when none.
const EditField* findField(FieldOwner owner, std::string_view name);
// The fields of `owner`, in order.
std::vector<const EditField*> fieldsOf(FieldOwner owner);

// "object", "light", "camera", "globals", "transblock", "tree".
const char* ownerName(FieldOwner owner);
// "number", "color", "vector", "choice", "text", "file", "transforms", "matrix".
const char* fieldKindName(FieldKind kind);

// A tree's name: how long it may be (the scenefile does not say; a name is for a person).
constexpr size_t kMaxTreeName = 128;
// The light types' and shapes' scenefile names.
const std::vector<std::string_view>& lightTypeNames();
const std::vector<std::string_view>& shapeNames();  // cube, cylinder, cone, sphere, torus, mesh

// An image made in code (the C++ API's texture handles: an index of Resources::images).
struct ImageHandle {
    int index = -1;
    bool operator==(const ImageHandle&) const = default;
};

// A field's value; which alternative goes with which kind: FieldKind above.
using FieldValue = std::variant<double, Vec3, std::string, std::vector<TransformOp>, Affine, ImageHandle>;

// A value for a field, as an edit gives it, with the text each of its numbers was typed as
// (empty: not typed; a save then writes the shortest text that reads back as the number).
struct FieldInput {
    const EditField* field = nullptr;
    FieldValue value;
    std::vector<std::string> typed = {};
};

}  // namespace ray::edit
