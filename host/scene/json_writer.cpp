// The course's JSON text of a scene document (json_writer.h).
#include "scene/json_writer.h"

#include <functional>
#include <set>

#include "core/message_text.h"
#include "scene/document_fields.h"
#include "scene/json_fields.h"
#include "scene/value_text.h"
#include "scene/xml_characters.h"

namespace fs = std::filesystem;

namespace ray {
namespace {

// ---------------------------------------------------------------------------------------
// What JSON cannot hold

const char* const kKeepXml = "or keep the scene in XML";

int sourceLine(const SceneDocument& document, SourceId id) {
    if (!document.source || id == kNoSource || id >= document.source->elementCount()) return 0;
    return document.source->element(id).line();
}

int lightLine(const SceneDocument& document, size_t index) {
    return index < document.lightSources.size() ? sourceLine(document, document.lightSources[index]) : 0;
}

// "a torus" with what names it where no line does ("a torus (object 4)").
std::string named(const std::string& what, int line, const std::string& node) {
    return line > 0 ? what : what + " (" + node + ")";
}

std::vector<JsonGap> lightGaps(const SceneDocument& document, size_t index) {
    const Light& light = document.lights[index];
    const int line = lightLine(document, index);
    const std::string node = "light " + std::to_string(index);
    std::vector<JsonGap> gaps;
    if (light.type == LightType::Area)
        gaps.push_back({line, named("an area light", line, node),
                        std::string("the course's JSON has point, directional and spot lights: use one of those, ") +
                            kKeepXml});
    else if (light.type == LightType::Spot && light.radius != Light{}.radius)
        gaps.push_back({line, named("a spot light's radius", line, node),
                        std::string("remove the <radius> (ray reads it but does not render it), ") + kKeepXml});
    return gaps;
}

std::vector<JsonGap> primitiveGaps(const PrimitiveNode& node) {
    const std::string id = "object " + std::to_string(node.id);
    std::vector<JsonGap> gaps;
    if (node.type == PrimitiveType::Torus)
        gaps.push_back({node.line, named("a torus", node.line, id),
                        std::string("the course's JSON has cube, sphere, cylinder, cone and mesh: use a mesh of a "
                                    "torus (an OBJ file), ") +
                            kKeepXml});
    if (node.material.emissive != Material{}.emissive)
        gaps.push_back({node.line, named("an emissive colour", node.line, id),
                        std::string("remove the <emissive> (the course's materials do not glow), ") + kKeepXml});
    return gaps;
}

std::vector<JsonGap> masterGaps(const SceneDocument& document, const MasterReference& master) {
    if (document.trees.count(master.name)) return {};
    return {{master.line,
             named("a master naming \"" + quotedForMessage(master.name) + "\" (no tree has that name)", master.line,
                   "node " + std::to_string(master.id)),
             "define the tree, or remove the master"}};
}

JsonGap csgGap(const CsgNode& csg) {
    return {csg.line, named("a csg object", csg.line, "node " + std::to_string(csg.id)),
            std::string("the course's JSON has no constructive solid geometry: model the shape otherwise, ") + kKeepXml};
}

// The block's own: what its items hold is found where they are written.
std::vector<JsonGap> blockGaps(const SceneDocument& document, const Block& block) {
    if (block.motion == Vec3{}) return {};
    const int line = sourceLine(document, block.source);
    return {{line, named("motion blur (<motion>)", line, "transblock " + std::to_string(block.id)),
             std::string("remove the <motion> (the course's scenes stand still), ") + kKeepXml}};
}

void treeGaps(const SceneDocument& document, const TreeNode& tree, std::vector<JsonGap>& gaps);

void itemGaps(const SceneDocument& document, const SceneItem& item, std::vector<JsonGap>& gaps) {
    auto add = [&](std::vector<JsonGap> more) { gaps.insert(gaps.end(), more.begin(), more.end()); };
    if (const auto* node = std::get_if<PrimitiveNode>(&item)) add(primitiveGaps(*node));
    else if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) treeGaps(document, **subtree, gaps);
    else if (const auto* master = std::get_if<MasterReference>(&item)) add(masterGaps(document, *master));
    else gaps.push_back(csgGap(*std::get<Box<CsgNode>>(item)));
}

void treeGaps(const SceneDocument& document, const TreeNode& tree, std::vector<JsonGap>& gaps) {
    for (const Block& block : tree.blocks) {
        for (const JsonGap& gap : blockGaps(document, block)) gaps.push_back(gap);
        for (const SceneItem& item : block.items) itemGaps(document, item, gaps);
    }
}

// A JSON number as RFC 8259 writes it: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?
bool isJsonNumber(std::string_view text) {
    size_t i = 0;
    auto digits = [&] {
        const size_t start = i;
        while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
        return i > start;
    };
    if (i < text.size() && text[i] == '-') ++i;
    if (i < text.size() && text[i] == '0') ++i;
    else if (!digits()) return false;
    if (i < text.size() && text[i] == '.') {
        ++i;
        if (!digits()) return false;
    }
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        if (!digits()) return false;
    }
    return i == text.size();
}

template <class Owner, size_t N>
const TripleField<Owner>* tripleField(const TripleField<Owner> (&fields)[N], const char* element) {
    for (const auto& field : fields)
        if (sameName(field.element, element)) return &field;
    return nullptr;
}

template <class Owner, size_t N>
const SingleField<Owner>* singleField(const SingleField<Owner> (&fields)[N], const char* element) {
    for (const auto& field : fields)
        if (sameName(field.element, element)) return &field;
    return nullptr;
}

const char* transformKey(TransformKind kind) {
    switch (kind) {
        case TransformKind::Translate: return "translate";
        case TransformKind::Rotate: return "rotate";
        case TransformKind::Scale: return "scale";
        case TransformKind::Matrix: break;
    }
    return "matrix";
}

// Where each group of a block's transforms starts: a run of transforms in T, R, S, Matrix
// order, one of each kind, is one JSON group (M = T·R·S·Matrix composes as the block does);
// a transform of a kind that cannot follow the one before it starts the next, nested group.
std::vector<size_t> transformRuns(const Block& block) {
    std::vector<size_t> starts{0};
    for (size_t i = 1; i < block.transforms.size(); ++i)
        if (block.transforms[i].kind <= block.transforms[i - 1].kind) starts.push_back(i);
    return starts;
}

// Whether the group is a template's placement alone: written as {"name": "..."}, which the
// reader takes for the template itself.
const MasterReference* placementAlone(const Block& block) {
    if (!block.transforms.empty() || block.motion != Vec3{} || block.items.size() != 1) return nullptr;
    return std::get_if<MasterReference>(&block.items.front());
}

void mastersIn(const TreeNode& tree, std::vector<std::string>& names) {
    for (const Block& block : tree.blocks)
        for (const SceneItem& item : block.items) {
            if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) mastersIn(**subtree, names);
            else if (const auto* master = std::get_if<MasterReference>(&item)) names.push_back(master->name);
        }
}

// The templates in the file's order, each after those it places: the course's reader finds
// a template named inside another only when it was defined before it (SPEC §7's quirk).
// A cycle is left as it is (the save's reading back refuses it).
std::vector<const NamedTree*> templatesInOrder(const SceneDocument& document) {
    std::vector<const NamedTree*> order;
    std::set<std::string> placed{"root"}, open;
    std::function<void(const NamedTree&)> visit = [&](const NamedTree& tree) {
        if (placed.count(tree.name) || !open.insert(tree.name).second) return;
        std::vector<std::string> names;
        mastersIn(tree.tree, names);
        for (const std::string& name : names)
            if (auto it = document.trees.find(name); it != document.trees.end()) visit(it->second);
        placed.insert(tree.name);
        order.push_back(&tree);
    };
    for (const NamedTree* tree : treesInOrder(const_cast<SceneDocument&>(document))) visit(*tree);
    return order;
}

// Whether the block holds no primitive and no placement, itself or in its inline trees: a
// group that held lights alone reads as such a block (its lights are the document's, written
// in groups of their own), and it would otherwise come back once more with every conversion.
bool holdsNothing(const Block& block) {
    for (const SceneItem& item : block.items) {
        const auto* subtree = std::get_if<Box<TreeNode>>(&item);
        if (!subtree) return false;
        for (const Block& inner : (*subtree)->blocks)
            if (!holdsNothing(inner)) return false;
    }
    return true;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Gaps

std::vector<JsonGap> jsonGaps(const SceneDocument& document) {
    std::vector<JsonGap> gaps;
    for (size_t i = 0; i < document.lights.size(); ++i)
        for (const JsonGap& gap : lightGaps(document, i)) gaps.push_back(gap);
    for (const NamedTree* tree : treesInOrder(const_cast<SceneDocument&>(document))) {
        if (tree->name.empty())
            gaps.push_back({tree->line, named("a tree with an empty name", tree->line, "a top-level tree"),
                            "name it: a JSON template is placed by its name"});
        treeGaps(document, tree->tree, gaps);
    }
    return gaps;
}

std::string jsonGapsMessage(const SceneDocument& document, const std::vector<JsonGap>& gaps) {
    const std::string file = document.file.empty() ? std::string() : quotedForMessage(document.file.string());
    auto where = [&](int line) {
        if (file.empty()) return std::string();
        return line > 0 ? file + ":" + std::to_string(line) + ": " : file + ": ";
    };
    const JsonGap& first = gaps.front();
    std::string message = where(first.line) + "error: " + first.feature +
                          " cannot be written in the course's JSON (SPEC §7 has no key for it); " + first.remedy;
    if (gaps.size() > 1) {
        constexpr size_t kListed = 6;
        message += "\n" + where(0) + "error: and " + std::to_string(gaps.size() - 1) + " more the JSON cannot hold:";
        for (size_t i = 1; i < gaps.size() && i <= kListed; ++i)
            message += std::string(i == 1 ? " " : "; ") + gaps[i].feature +
                       (gaps[i].line > 0 ? " on line " + std::to_string(gaps[i].line) : std::string());
        if (gaps.size() - 1 > kListed) message += "; ...";
    }
    return message;
}

std::string jsonString(const std::string& text, const std::string& what) {
    std::string out = "\"";
    for (size_t i = 0; i < text.size();) {
        const std::optional<Utf8Character> c = decodeUtf8(text, i);
        if (!c)
            throw InputError("error: the " + what + " '" + quotedForMessage(shownAsUtf8(text), 60) +
                             "' is not UTF-8 text, which a JSON file must be; rename it to save the scene as JSON");
        const std::string_view bytes(text.data() + i, c->bytes);
        i += c->bytes;
        switch (c->code) {
            case '"': out += "\\\""; continue;
            case '\\': out += "\\\\"; continue;
            case '\n': out += "\\n"; continue;
            case '\t': out += "\\t"; continue;
            case '\r': out += "\\r"; continue;
            case '\b': out += "\\b"; continue;
            case '\f': out += "\\f"; continue;
            default: break;
        }
        if (c->code < 0x20) {
            static const char kHex[] = "0123456789abcdef";
            out += "\\u00";
            out += kHex[c->code >> 4];
            out += kHex[c->code & 0xF];
        } else {
            out += bytes;
        }
    }
    return out + "\"";
}

// ---------------------------------------------------------------------------------------
// The writer

// File names are relative to the folder above the target's folder: FileReferences takes
// the folder of the path it is given, so it is given the target's folder.
JsonWriter::JsonWriter(const SceneDocument& document, const Resources& resources, const fs::path& target,
                       TextStyle style)
    : document_(document), resources_(resources), references_([&] {
          std::error_code ec;
          return fs::absolute(target, ec).parent_path();
      }()),
      style_(std::move(style)) {}

void JsonWriter::refuseGaps(std::vector<JsonGap> gaps) const {
    if (!gaps.empty()) throw InputError(jsonGapsMessage(document_, gaps));
}

std::string JsonWriter::object(const Members& members, const std::string& indent) const {
    if (members.empty()) return "{}";
    std::string out = "{";
    for (size_t i = 0; i < members.size(); ++i)
        out += style_.newline + deeper(indent) + "\"" + members[i].first + "\": " + members[i].second +
               (i + 1 < members.size() ? "," : "");
    return out + style_.newline + indent + "}";
}

std::string JsonWriter::array(const std::vector<std::string>& values, const std::string& indent) const {
    if (values.empty()) return "[]";
    std::string out = "[";
    for (size_t i = 0; i < values.size(); ++i)
        out += style_.newline + deeper(indent) + values[i] + (i + 1 < values.size() ? "," : "");
    return out + style_.newline + indent + "]";
}

// The number as the user typed it where that is a JSON number too (SceneDocument::
// typedNumbers), else the shortest text that reads back as it.
std::string JsonWriter::number(const std::string& key, double value) const {
    std::string text = typedNumberText(document_, key, value);
    return isJsonNumber(text) ? text : shortestNumber(value);
}

std::string JsonWriter::triple(const std::string& owner, const char* element, const Vec3& v) const {
    return "[" + number(numberKey(owner, element, 0), v.x) + ", " + number(numberKey(owner, element, 1), v.y) + ", " +
           number(numberKey(owner, element, 2), v.z) + "]";
}

std::string JsonWriter::document() {
    refuseGaps(jsonGaps(document_));
    const std::string member = deeper(""), element = deeper(member);
    Members members{{"name", "\"root\""}, {"globalData", globals(member)}, {"cameraData", camera(member)}};
    std::vector<std::string> templates, groups;
    for (const NamedTree* tree : templatesInOrder(document_)) templates.push_back(templateGroup(*tree, element));
    if (!templates.empty()) members.emplace_back("templateGroups", array(templates, member));
    for (size_t i = 0; i < document_.lights.size(); ++i) groups.push_back(lightGroup(i, element));
    if (auto root = document_.trees.find("root"); root != document_.trees.end())
        for (const Block& block : root->second.tree.blocks)
            if (!holdsNothing(block)) groups.push_back(group(block, element));
    members.emplace_back("groups", array(groups, member));
    return object(members, "") + style_.newline;
}

std::string JsonWriter::globals(const std::string& indent) {
    Members members;
    for (const JsonKey& key : kJsonGlobalsKeys) {
        const SingleField<GlobalCoefficients>* field = singleField(kGlobalsSingles, key.element);
        members.emplace_back(key.key, number(numberKey("globals", field->element, 0), document_.globals.*field->member));
    }
    return object(members, indent);
}

// Every key the course's reader requires (position, up, heightAngle, look), and the lens's
// where it is not a pinhole's.
std::string JsonWriter::camera(const std::string& indent) {
    const Camera& camera = document_.camera;
    const Camera defaults;
    Members members;
    for (const JsonKey& key : kJsonCameraKeys) {
        if (const auto* field = tripleField(kCameraTriples, key.element)) {
            members.emplace_back(key.key, triple("camera", field->element, camera.*field->member));
        } else if (const auto* single = singleField(kCameraSingles, key.element)) {
            if (single->member == &Camera::heightAngleDegrees || camera.*single->member != defaults.*single->member)
                members.emplace_back(key.key, number(numberKey("camera", single->element, 0), camera.*single->member));
        }
    }
    return object(members, indent);
}

std::string JsonWriter::light(size_t index, const std::string& indent) {
    refuseGaps(lightGaps(document_, index));
    const Light& light = document_.lights[index];
    const std::string owner = "light " + std::to_string(index);
    const unsigned type = lightTypeBit(light.type);
    Members members{{"type", std::string("\"") + lightTypeName(light.type) + "\""}};
    for (const JsonKey& key : kJsonLightKeys) {
        if (const auto* field = tripleField(kLightTriples, key.element)) {
            if (field->lights & type) members.emplace_back(key.key, triple(owner, field->element, light.*field->member));
        } else if (const auto* single = singleField(kLightSingles, key.element)) {
            if (single->lights & type)
                members.emplace_back(key.key, number(numberKey(owner, single->element, 0), light.*single->member));
        }
    }
    return object(members, indent);
}

// The light's position is its group's translate: the reader places a light at CTM · origin.
std::string JsonWriter::lightGroup(size_t index, const std::string& indent) {
    const Light& placed = document_.lights[index];
    Members members;
    if (kPositionedLights & lightTypeBit(placed.type))
        members.emplace_back("translate", triple("light " + std::to_string(index), "position", placed.position));
    members.emplace_back("lights", array({light(index, deeper(deeper(indent)))}, deeper(indent)));
    return object(members, indent);
}

std::string JsonWriter::transformValue(const Block& block, size_t index, const std::string& indent) const {
    const TransformOp& op = block.transforms[index];
    const std::string owner = "block " + std::to_string(block.id), field = "transform " + std::to_string(index);
    auto values = [&](size_t first, size_t count) {
        std::string text = "[";
        for (size_t i = first; i < first + count; ++i)
            text += (i > first ? ", " : "") + number(numberKey(owner, field, i), op.v[i]);
        return text + "]";
    };
    switch (op.kind) {
        case TransformKind::Translate:
        case TransformKind::Scale: return values(0, 3);
        case TransformKind::Rotate: return values(0, 4);
        case TransformKind::Matrix: break;
    }
    // Four rows of four, as written: the translation is the last column.
    return array({values(0, 4), values(4, 4), values(8, 4), "[0, 0, 0, 1]"}, indent);
}

std::string JsonWriter::group(const Block& block, const std::string& indent) { return namedGroup(block, "", indent); }

std::string JsonWriter::namedGroup(const Block& block, const std::string& name, const std::string& indent) {
    refuseGaps(blockGaps(document_, block));
    if (name.empty())
        if (const MasterReference* placement = placementAlone(block)) {
            refuseGaps(masterGaps(document_, *placement));
            return object({{"name", jsonString(placement->name, "master name")}}, indent);
        }
    return nestedGroup(block, 0, transformRuns(block), name, indent);
}

// Group `run` of the block's transforms, holding the next run's group, or (the last) what
// the block holds.
std::string JsonWriter::nestedGroup(const Block& block, size_t run, const std::vector<size_t>& runStarts,
                                    const std::string& name, const std::string& indent) {
    Members members;
    if (!name.empty()) members.emplace_back("name", jsonString(name, "tree name"));
    const size_t end = run + 1 < runStarts.size() ? runStarts[run + 1] : block.transforms.size();
    for (size_t i = runStarts[run]; i < end; ++i)
        members.emplace_back(transformKey(block.transforms[i].kind), transformValue(block, i, deeper(indent)));
    if (run + 1 < runStarts.size()) {
        members.emplace_back("groups", array({nestedGroup(block, run + 1, runStarts, "", deeper(deeper(indent)))},
                                             deeper(indent)));
    } else {
        for (auto& member : contentMembers(block, deeper(indent))) members.push_back(std::move(member));
    }
    return object(members, indent);
}

// "primitives": the primitives before any other item; "groups": the rest, in order (a
// primitive after another item goes in a group of its own run, so that it keeps its place).
JsonWriter::Members JsonWriter::contentMembers(const Block& block, const std::string& indent) {
    const std::string element = deeper(indent);
    std::vector<std::string> primitives, groups;
    size_t i = 0;
    for (; i < block.items.size() && std::holds_alternative<PrimitiveNode>(block.items[i]); ++i)
        primitives.push_back(primitive(std::get<PrimitiveNode>(block.items[i]), element));
    while (i < block.items.size()) {
        const SceneItem& item = block.items[i];
        if (std::holds_alternative<PrimitiveNode>(item)) {
            std::vector<std::string> run;
            for (; i < block.items.size() && std::holds_alternative<PrimitiveNode>(block.items[i]); ++i)
                run.push_back(primitive(std::get<PrimitiveNode>(block.items[i]), deeper(deeper(element))));
            groups.push_back(object({{"primitives", array(run, deeper(element))}}, element));
            continue;
        }
        if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
            for (const Block& inner : (*subtree)->blocks)
                if (!holdsNothing(inner)) groups.push_back(group(inner, element));
        } else if (const auto* master = std::get_if<MasterReference>(&item)) {
            refuseGaps(masterGaps(document_, *master));
            groups.push_back(object({{"name", jsonString(master->name, "master name")}}, element));
        } else {
            refuseGaps({csgGap(*std::get<Box<CsgNode>>(item))});
        }
        ++i;
    }
    Members members;
    if (!primitives.empty()) members.emplace_back("primitives", array(primitives, indent));
    if (!groups.empty()) members.emplace_back("groups", array(groups, indent));
    return members;
}

std::string JsonWriter::templateGroup(const NamedTree& tree, const std::string& indent) {
    if (tree.name.empty())
        refuseGaps({{tree.line, "a tree with an empty name", "name it: a JSON template is placed by its name"}});
    if (tree.tree.blocks.size() == 1) return namedGroup(tree.tree.blocks.front(), tree.name, indent);
    std::vector<std::string> groups;
    for (const Block& block : tree.tree.blocks)
        if (!holdsNothing(block)) groups.push_back(group(block, deeper(deeper(indent))));
    Members members{{"name", jsonString(tree.name, "tree name")}};
    if (!groups.empty()) members.emplace_back("groups", array(groups, deeper(indent)));
    return object(members, indent);
}

// The fields that differ from a default material's, and a transparent material's index of
// refraction always (the course's reader takes a missing "ior" as 0, ray's as 1).
std::string JsonWriter::primitive(const PrimitiveNode& node, const std::string& indent) {
    refuseGaps(primitiveGaps(node));
    const std::string owner = "object " + std::to_string(node.id);
    const Material& m = node.material;
    const Material defaults;
    Members members{{"type", std::string("\"") + primitiveTypeName(node.type) + "\""}};
    if (node.type == PrimitiveType::Mesh)
        members.emplace_back("meshFile", jsonString(meshFileOf(node, resources_, references_), "mesh file"));
    for (const JsonKey& key : kJsonMaterialKeys) {
        if (const auto* field = tripleField(kMaterialTriples, key.element)) {
            if (m.*field->member != defaults.*field->member)
                members.emplace_back(key.key, triple(owner, field->element, m.*field->member));
        } else if (const auto* single = singleField(kMaterialSingles, key.element)) {
            const bool transparentIor = single->member == &Material::ior && m.transparent != defaults.transparent;
            if (m.*single->member != defaults.*single->member || transparentIor)
                members.emplace_back(key.key, number(numberKey(owner, single->element, 0), m.*single->member));
        }
    }
    for (const bool bumpMap : {false, true}) {
        const std::string file = imageFileOf(node, bumpMap, resources_, references_);
        if (file.empty()) continue;
        const char* element = bumpMap ? "bumpmap" : "texture";
        const TextureMap& map = bumpMap ? m.bumpMap : m.texture;
        const std::string prefix = bumpMap ? "bumpMap" : "texture";
        members.emplace_back(prefix + "File", jsonString(file, bumpMap ? "bump map file" : "texture file"));
        members.emplace_back(prefix + "U", number(numberKey(owner, element, 0), map.repeatU));
        members.emplace_back(prefix + "V", number(numberKey(owner, element, 1), map.repeatV));
    }
    return object(members, indent);
}

std::string documentToJson(const SceneDocument& document, const Resources& resources, const fs::path& target) {
    return JsonWriter(document, resources, target).document();
}

}  // namespace ray
