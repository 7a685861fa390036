#include "edit/field_table.h"

#include "scene/document_fields.h"

namespace ray::edit {

namespace {

// The images a texture or bump map may name (PNG and JPEG read by ray itself, the others
// through OpenImageIO: image/image.h).
const std::vector<std::string_view> kImageExtensions{".png", ".jpg", ".jpeg", ".ppm", ".pgm", ".bmp",
                                                      ".tga", ".tif", ".tiff", ".gif", ".hdr", ".exr"};

// An entry for each number a node's element holds, from the saver's own table.
template <class Owner, size_t Count>
void addTriples(std::vector<EditField>& table, FieldOwner owner, std::string_view group,
                const TripleField<Owner> (&triples)[Count], bool colors) {
    for (const TripleField<Owner>& f : triples) {
        const bool color = colors && f.attributes[0] == kRgb[0];
        table.push_back({.owner = owner, .group = group, .name = f.element,
                         .kind = color ? FieldKind::Color : FieldKind::Vector, .help = f.help, .rule = f.rule,
                         .lights = f.lights, .nonzero = f.nonzero, .member = f.member});
    }
}

template <class Owner, size_t Count>
void addSingles(std::vector<EditField>& table, FieldOwner owner, std::string_view group,
                const SingleField<Owner> (&singles)[Count]) {
    for (const SingleField<Owner>& f : singles)
        table.push_back({.owner = owner, .group = group, .name = f.element, .kind = FieldKind::Number,
                         .help = f.help, .rule = f.rule, .lights = f.lights, .member = f.member});
}

inline constexpr NumberRule kRepeat{0, false, rules::kUnbounded, true,
                                    "it is how many times the image repeats across the surface"};

// A texture's or bump map's three fields: its file and its repeats.
void addImageFields(std::vector<EditField>& table, std::string_view group, std::string_view file,
                    std::string_view u, std::string_view v, SpecialField fileField, SpecialField uField,
                    SpecialField vField, std::string_view what) {
    table.push_back({.owner = FieldOwner::Object, .group = group, .name = file, .kind = FieldKind::File,
                     .help = what, .special = fileField, .extensions = kImageExtensions});
    table.push_back({.owner = FieldOwner::Object, .group = group, .name = u, .kind = FieldKind::Number,
                     .help = "how many times the image repeats along u", .rule = &kRepeat, .special = uField});
    table.push_back({.owner = FieldOwner::Object, .group = group, .name = v, .kind = FieldKind::Number,
                     .help = "how many times the image repeats along v", .rule = &kRepeat, .special = vField});
}

std::vector<EditField> makeTable() {
    std::vector<EditField> table;
    addTriples(table, FieldOwner::Object, "material", kMaterialTriples, true);
    addSingles(table, FieldOwner::Object, "material", kMaterialSingles);
    addImageFields(table, "texture", "texture", "texture.u", "texture.v", SpecialField::Texture,
                   SpecialField::TextureU, SpecialField::TextureV,
                   "an image in the scene's folder, mixed with the diffuse color by blend; \"\" for none");
    addImageFields(table, "bump map", "bumpmap", "bumpmap.u", "bumpmap.v", SpecialField::BumpMap,
                   SpecialField::BumpMapU, SpecialField::BumpMapV,
                   "an image in the scene's folder whose brightness bumps the surface; \"\" for none");
    table.push_back({.owner = FieldOwner::Object, .group = "transform", .name = "transform",
                     .kind = FieldKind::Transforms,
                     .help = "the object's own transforms (translate, rotate, scale, matrix), the last applied first; "
                             "setting them moves this object alone",
                     .special = SpecialField::Transforms});
    table.push_back({.owner = FieldOwner::Object, .group = "transform", .name = "world", .kind = FieldKind::Matrix,
                     .help = "where the object is: its object-to-world matrix at its first placement, three rows",
                     .special = SpecialField::World});
    table.push_back({.owner = FieldOwner::Light, .group = "light", .name = "type", .kind = FieldKind::Choice,
                     .help = "what kind of light it is", .special = SpecialField::LightType,
                     .choices = lightTypeNames()});
    addTriples(table, FieldOwner::Light, "light", kLightTriples, true);
    addSingles(table, FieldOwner::Light, "light", kLightSingles);
    addTriples(table, FieldOwner::Camera, "camera", kCameraTriples, false);
    addSingles(table, FieldOwner::Camera, "camera", kCameraSingles);
    addSingles(table, FieldOwner::Globals, "globals", kGlobalsSingles);
    table.push_back({.owner = FieldOwner::Block, .group = "transform", .name = "transform",
                     .kind = FieldKind::Transforms,
                     .help = "the transblock's transforms, the last applied first: they move everything in it",
                     .special = SpecialField::Transforms});
    table.push_back({.owner = FieldOwner::Tree, .group = "tree", .name = "name", .kind = FieldKind::Text,
                     .help = "the tree's name, by which masters place it (root is the scene's own)",
                     .special = SpecialField::TreeName, .maxLength = kMaxTreeName});
    return table;
}

}  // namespace

std::string EditField::keyword() const {
    std::string word(name);
    for (char& c : word)
        if (c == '.') c = '_';
    return word;
}

const std::vector<EditField>& editFields() {
    static const std::vector<EditField> table = makeTable();
    return table;
}

const EditField* findField(FieldOwner owner, std::string_view name) {
    for (const EditField& field : editFields())
        if (field.owner == owner && (field.name == name || field.keyword() == name)) return &field;
    return nullptr;
}

std::vector<const EditField*> fieldsOf(FieldOwner owner) {
    std::vector<const EditField*> fields;
    for (const EditField& field : editFields())
        if (field.owner == owner) fields.push_back(&field);
    return fields;
}

const char* ownerName(FieldOwner owner) {
    switch (owner) {
        case FieldOwner::Object: return "object";
        case FieldOwner::Light: return "light";
        case FieldOwner::Camera: return "camera";
        case FieldOwner::Globals: return "globals";
        case FieldOwner::Block: return "transblock";
        case FieldOwner::Tree: return "tree";
    }
    return "?";
}

const char* fieldKindName(FieldKind kind) {
    switch (kind) {
        case FieldKind::Number: return "number";
        case FieldKind::Color: return "color";
        case FieldKind::Vector: return "vector";
        case FieldKind::Choice: return "choice";
        case FieldKind::Text: return "text";
        case FieldKind::File: return "file";
        case FieldKind::Transforms: return "transforms";
        case FieldKind::Matrix: return "matrix";
    }
    return "?";
}

const std::vector<std::string_view>& lightTypeNames() {
    // In the order of LightType, as lightTypeName spells them.
    static const std::vector<std::string_view> names{lightTypeName(LightType::Point),
                                                     lightTypeName(LightType::Directional),
                                                     lightTypeName(LightType::Spot), lightTypeName(LightType::Area)};
    return names;
}

const std::vector<std::string_view>& shapeNames() {
    static const std::vector<std::string_view> names{
        primitiveTypeName(PrimitiveType::Cube), primitiveTypeName(PrimitiveType::Cylinder),
        primitiveTypeName(PrimitiveType::Cone), primitiveTypeName(PrimitiveType::Sphere),
        primitiveTypeName(PrimitiveType::Torus), primitiveTypeName(PrimitiveType::Mesh)};
    return names;
}

}  // namespace ray::edit
