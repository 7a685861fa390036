// The canonical text of a scene document (canonical_writer.h).
#include "scene/canonical_writer.h"

#include "core/message_text.h"
#include "scene/document_fields.h"
#include "scene/value_text.h"
#include "scene/xml_characters.h"

namespace fs = std::filesystem;

namespace ray {
namespace {

const char* csgOperationName(CsgStepKind kind) {
    switch (kind) {
        case CsgStepKind::Intersection: return "intersection";
        case CsgStepKind::Difference: return "difference";
        default: return "union";
    }
}

[[noreturn]] void unsaveable(const PrimitiveNode& node, const char* what) {
    throw InputError(std::string("error: object ") + std::to_string(node.id) + " uses a " + what +
                     " made in memory, which a scenefile cannot hold; make it from a file to save the scene");
}

std::string attribute(const char* name, const std::string& value) {
    return std::string(" ") + name + "=\"" + value + "\"";
}

}  // namespace

std::string escapedAttribute(const std::string& text, std::string_view what) {
    if (const std::optional<UnwritableCharacter> found = firstUnwritableCharacter(text)) {
        const std::string quoted = std::string(what) + " '" + quotedForMessage(shownAsUtf8(text), 60) + "'";
        throw InputError("error: " + unwritableSentence(quoted, *found) + "; rename it to save the scene");
    }
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            // Written as themselves, a reader would take them for blanks (attribute-value
            // normalization): as references they read back as they are.
            case '\t': out += "&#9;"; break;
            case '\n': out += "&#10;"; break;
            case '\r': out += "&#13;"; break;
            default: out += c;
        }
    }
    return out;
}

FileReferences::FileReferences(const fs::path& target) {
    std::error_code ec;
    folder_ = fs::weakly_canonical(fs::absolute(target, ec).parent_path(), ec);
}

std::string FileReferences::relative(const fs::path& file) const {
    std::error_code ec;
    fs::path absolute = fs::weakly_canonical(fs::absolute(file, ec), ec);
    fs::path relative = absolute.lexically_relative(folder_);
    return (relative.empty() ? absolute : relative).generic_string();
}

bool FileReferences::sameFolderAs(const fs::path& documentFile) const {
    std::error_code ec;
    return fs::weakly_canonical(fs::absolute(documentFile, ec).parent_path(), ec) == folder_;
}

std::string imageFileOf(const PrimitiveNode& node, bool bumpMap, const Resources& resources,
                        const FileReferences& references) {
    const char* what = bumpMap ? "bump map" : "texture";
    const int image = bumpMap ? node.material.bumpMap.image : node.material.texture.image;
    if (node.files) {
        const std::optional<ImageReference>& file = bumpMap ? node.files->bumpMap : node.files->texture;
        const std::string& missing = bumpMap ? node.files->missingBumpMap : node.files->missingTexture;
        if (file) return references.relative(file->file);
        if (!missing.empty()) return missing;
    }
    if (image < 0) return "";
    if (size_t(image) >= resources.imageFiles.size() || resources.imageFiles[size_t(image)] == "<memory>")
        unsaveable(node, what);
    return references.relative(resources.imageFiles[size_t(image)]);
}

std::string meshFileOf(const PrimitiveNode& node, const Resources& resources, const FileReferences& references) {
    if (node.files && !node.files->meshFile.empty()) return references.relative(node.files->meshFile);
    if (node.mesh >= 0 && size_t(node.mesh) < resources.meshFiles.size() &&
        resources.meshFiles[size_t(node.mesh)] != "<memory>")
        return references.relative(resources.meshFiles[size_t(node.mesh)]);
    unsaveable(node, "mesh");
}

CanonicalWriter::CanonicalWriter(const SceneDocument& document, const Resources& resources, const fs::path& target,
                                 TextStyle style)
    : document_(document), resources_(resources), references_(target), style_(std::move(style)) {}

std::string CanonicalWriter::number(const std::string& key, double value) const {
    return typedNumberText(document_, key, value);
}

std::string CanonicalWriter::indented(const std::string& indent, int depth) const {
    std::string text = style_.newline + indent;
    for (int i = 0; i < depth; ++i) text += style_.indentUnit;
    return text;
}

std::string CanonicalWriter::document() {
    std::string out = "<scenefile>";
    const std::string indent = style_.indentUnit;
    out += indented("", 1) + globals(indent);
    out += indented("", 1) + camera(indent);
    for (size_t i = 0; i < document_.lights.size(); ++i) out += indented("", 1) + light(i, indent);
    // The Walker's order: the file's, then trees made in code.
    for (const NamedTree* tree : treesInOrder(const_cast<SceneDocument&>(document_)))
        out += indented("", 1) + namedTree(*tree, indent);
    return out + style_.newline + "</scenefile>" + style_.newline;
}

template <class Owner, class Field>
std::string CanonicalWriter::tripleElement(const Owner& owner, const Field& field, const std::string& key) {
    const Vec3& v = owner.*field.member;
    const double values[] = {v.x, v.y, v.z};
    std::string text = std::string("<") + field.element;
    for (size_t i = 0; i < 3; ++i)
        text += attribute(field.attributes[i], number(numberKey(key, field.element, i), values[i]));
    return text + "/>";
}

std::string CanonicalWriter::globalsElement(const char* element) {
    for (const auto& field : kGlobalsSingles)
        if (sameName(field.element, element))
            return std::string("<") + field.element +
                   attribute("v", number(numberKey("globals", field.element, 0), document_.globals.*field.member)) +
                   "/>";
    return "";
}

std::string CanonicalWriter::globals(const std::string& indent) {
    std::string out = "<globaldata>";
    for (const auto& field : kGlobalsSingles) out += indented(indent, 1) + globalsElement(field.element);
    return out + indented(indent, 0) + "</globaldata>";
}

std::string CanonicalWriter::cameraElement(const char* element) {
    const Camera& c = document_.camera;
    for (const auto& field : kCameraTriples)
        if (sameName(field.element, element)) return tripleElement(c, field, "camera");
    for (const auto& field : kCameraSingles)
        if (sameName(field.element, element))
            return std::string("<") + field.element +
                   attribute("v", number(numberKey("camera", field.element, 0), c.*field.member)) + "/>";
    return "";
}

std::string CanonicalWriter::camera(const std::string& indent) {
    std::string out = "<cameradata>";
    const Camera defaults;
    for (const auto& field : kCameraTriples) out += indented(indent, 1) + cameraElement(field.element);
    for (const auto& field : kCameraSingles)
        if (field.member == &Camera::heightAngleDegrees || document_.camera.*field.member != defaults.*field.member)
            out += indented(indent, 1) + cameraElement(field.element);
    return out + indented(indent, 0) + "</cameradata>";
}

std::string CanonicalWriter::lightElement(size_t index, const char* element) {
    const Light& l = document_.lights[index];
    const std::string owner = "light " + std::to_string(index);
    if (sameName(element, "type")) return std::string("<type v=\"") + lightTypeName(l.type) + "\"/>";
    for (const auto& field : kLightTriples)
        if (sameName(field.element, element)) return tripleElement(l, field, owner);
    for (const auto& field : kLightSingles)
        if (sameName(field.element, element))
            return std::string("<") + field.element +
                   attribute("v", number(numberKey(owner, field.element, 0), l.*field.member)) + "/>";
    return "";
}

// A light's type, color and attenuation, and whatever else differs from a default.
std::string CanonicalWriter::light(size_t index, const std::string& indent) {
    const Light& l = document_.lights[index];
    const Light defaults;
    std::string out = "<lightdata>";
    out += indented(indent, 1) + "<id v=\"" + std::to_string(index) + "\"/>";
    out += indented(indent, 1) + lightElement(index, "type");
    for (const auto& field : kLightTriples)
        if (field.member == &Light::color || field.member == &Light::attenuation ||
            l.*field.member != defaults.*field.member)
            out += indented(indent, 1) + lightElement(index, field.element);
    for (const auto& field : kLightSingles)
        if (l.*field.member != defaults.*field.member) out += indented(indent, 1) + lightElement(index, field.element);
    return out + indented(indent, 0) + "</lightdata>";
}

std::string CanonicalWriter::namedTree(const NamedTree& named, const std::string& indent) {
    const std::string open = "<object type=\"tree\" name=\"" + escapedAttribute(named.name, "tree name") + "\">";
    return tree(named.tree, open.c_str(), indent);
}

std::string CanonicalWriter::tree(const TreeNode& node, const char* open, const std::string& indent) {
    std::string out = open;
    const std::string inner = indented(indent, 1).substr(style_.newline.size());
    for (const Block& b : node.blocks) out += indented(indent, 1) + block(b, inner);
    return out + indented(indent, 0) + "</object>";
}

std::string CanonicalWriter::transform(const Block& b, size_t index, const std::string& indent) {
    const TransformOp& op = b.transforms[index];
    const std::string owner = "block " + std::to_string(b.id), field = "transform " + std::to_string(index);
    auto value = [&](size_t i) { return number(numberKey(owner, field, i), op.v[i]); };
    switch (op.kind) {
        case TransformKind::Translate:
        case TransformKind::Scale:
            return std::string(op.kind == TransformKind::Translate ? "<translate" : "<scale") + attribute("x", value(0)) +
                   attribute("y", value(1)) + attribute("z", value(2)) + "/>";
        case TransformKind::Rotate:
            return "<rotate" + attribute("x", value(0)) + attribute("y", value(1)) + attribute("z", value(2)) +
                   attribute("angle", value(3)) + "/>";
        case TransformKind::Matrix: break;
    }
    static const char* const kRows[] = {"<row0", "<row1", "<row2", "<row3"};
    static const char* const kColumns[] = {"v1", "v2", "v3", "v4"};
    std::string out = "<matrix>";
    for (size_t r = 0; r < 4; ++r) {
        out += indented(indent, 1) + kRows[r];
        for (size_t c = 0; c < 4; ++c)
            out += attribute(kColumns[c], r < 3 ? value(4 * r + c) : std::string(c == 3 ? "1" : "0"));
        out += "/>";
    }
    return out + indented(indent, 0) + "</matrix>";
}

std::string CanonicalWriter::motion(const Block& b) {
    const std::string owner = "block " + std::to_string(b.id);
    return "<motion" + attribute("x", number(numberKey(owner, "motion", 0), b.motion.x)) +
           attribute("y", number(numberKey(owner, "motion", 1), b.motion.y)) +
           attribute("z", number(numberKey(owner, "motion", 2), b.motion.z)) + "/>";
}

std::string CanonicalWriter::block(const Block& b, const std::string& indent) {
    if (keptBlock)
        if (std::optional<std::string> kept = keptBlock(b, indent)) return *kept;
    const std::string inner = indented(indent, 1).substr(style_.newline.size());
    std::string out = "<transblock>";
    for (size_t i = 0; i < b.transforms.size(); ++i) out += indented(indent, 1) + transform(b, i, inner);
    if (b.motion != Vec3{}) out += indented(indent, 1) + motion(b);
    for (const SceneItem& i : b.items) out += indented(indent, 1) + item(i, inner);
    return out + indented(indent, 0) + "</transblock>";
}

std::string CanonicalWriter::item(const SceneItem& i, const std::string& indent) {
    if (keptItem)
        if (std::optional<std::string> kept = keptItem(i, indent)) return *kept;
    if (const auto* primitiveNode = std::get_if<PrimitiveNode>(&i)) return primitive(*primitiveNode, indent);
    if (const auto* subtree = std::get_if<Box<TreeNode>>(&i)) return tree(**subtree, "<object type=\"tree\">", indent);
    if (const auto* master = std::get_if<MasterReference>(&i))
        return "<object type=\"master\" name=\"" + escapedAttribute(master->name, "master name") + "\"/>";
    return csg(*std::get<Box<CsgNode>>(i), indent);
}

std::string CanonicalWriter::csg(const CsgNode& node, const std::string& indent) {
    std::string out = std::string("<object type=\"csg\" operation=\"") + csgOperationName(node.operation) + "\">";
    const std::string inner = indented(indent, 1).substr(style_.newline.size());
    for (const TreeNode& o : node.operands) out += indented(indent, 1) + operand(o, inner);
    return out + indented(indent, 0) + "</object>";
}

std::string CanonicalWriter::operand(const TreeNode& o, const std::string& indent) {
    if (o.blocks.size() == 1) return block(o.blocks.front(), indent);
    // Not made by the loader; one operand all the same.
    const std::string inner = indented(indent, 1).substr(style_.newline.size());
    return "<transblock>" + indented(indent, 1) + tree(o, "<object type=\"tree\">", inner) + indented(indent, 0) +
           "</transblock>";
}

std::string CanonicalWriter::materialElement(const PrimitiveNode& node, const char* element) {
    const std::string owner = "object " + std::to_string(node.id);
    for (const auto& field : kMaterialTriples)
        if (sameName(field.element, element)) return tripleElement(node.material, field, owner);
    for (const auto& field : kMaterialSingles)
        if (sameName(field.element, element))
            return std::string("<") + field.element +
                   attribute("v", number(numberKey(owner, field.element, 0), node.material.*field.member)) + "/>";
    return "";
}

std::string CanonicalWriter::mapElement(const PrimitiveNode& node, bool bumpMap) {
    const std::string file = imageFileOf(node, bumpMap, resources_, references_);
    if (file.empty()) return "";
    const char* name = bumpMap ? "bumpmap" : "texture";
    const TextureMap& map = bumpMap ? node.material.bumpMap : node.material.texture;
    const std::string owner = "object " + std::to_string(node.id);
    const std::string written = escapedAttribute(file, bumpMap ? "bump map file" : "texture file");
    return std::string("<") + name + attribute("file", written) +
           attribute("u", number(numberKey(owner, name, 0), map.repeatU)) +
           attribute("v", number(numberKey(owner, name, 1), map.repeatV)) + "/>";
}

// The fields that differ from a default material's.
std::string CanonicalWriter::primitive(const PrimitiveNode& node, const std::string& indent) {
    std::string out = std::string("<object type=\"primitive\" name=\"") + primitiveTypeName(node.type) + "\"";
    if (node.type == PrimitiveType::Mesh)
        out += attribute("meshfile", escapedAttribute(meshFileOf(node, resources_, references_), "mesh file"));
    std::string fields;
    const Material& m = node.material;
    const Material defaults;
    for (const auto& field : kMaterialTriples)
        if (m.*field.member != defaults.*field.member) fields += indented(indent, 1) + materialElement(node, field.element);
    for (const auto& field : kMaterialSingles)
        if (m.*field.member != defaults.*field.member) fields += indented(indent, 1) + materialElement(node, field.element);
    for (const bool bumpMap : {false, true})
        if (std::string map = mapElement(node, bumpMap); !map.empty()) fields += indented(indent, 1) + map;
    if (fields.empty()) return out + "/>";
    return out + ">" + fields + indented(indent, 0) + "</object>";
}

}  // namespace ray
