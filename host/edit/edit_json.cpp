#include "edit/edit_json.h"

#include <cmath>
#include <vector>

#include "core/message_text.h"
#include "edit/field_values.h"

namespace ray::edit {

using nlohmann::json;

namespace {

// ---------------------------------------------------------------------------------------
// Reading, with each number's text

std::string escapePointer(std::string_view token) {
    std::string out;
    for (char c : token) {
        if (c == '~') out += "~0";
        else if (c == '/') out += "~1";
        else out += c;
    }
    return out;
}

// Builds the document as nlohmann's own DOM parser would, and keeps the text of every
// number that is not a whole number (those are written as JSON wrote them anyway).
class TypedParser : public nlohmann::json_sax<json> {
public:
    TypedJson result;
    std::string error;

    bool null() override { return add(nullptr); }
    bool boolean(bool value) override { return add(value); }
    bool number_integer(number_integer_t value) override { return add(value); }
    bool number_unsigned(number_unsigned_t value) override { return add(value); }
    bool number_float(number_float_t value, const string_t& text) override {
        if (!add(value)) return false;
        result.typed[lastPointer_] = text;
        return true;
    }
    bool string(string_t& value) override { return add(value); }
    bool binary(binary_t&) override { return fail("binary values are not JSON"); }
    bool start_object(std::size_t) override { return open(json::object()); }
    bool key(string_t& key) override {
        key_ = key;
        return true;
    }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override { return open(json::array()); }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
        const std::string why = e.what();
        const size_t at = why.find("parse error");
        return fail("the request is not JSON at byte " + std::to_string(position) + ": " +
                    quotedForMessage(at == std::string::npos ? why : why.substr(at), 120));
    }

private:
    bool fail(const std::string& why) {
        error = why;
        return false;
    }

    // The value placed where the parse is; its pointer in lastPointer_.
    json* place(json value) {
        if (stack_.empty()) {
            result.value = std::move(value);
            lastPointer_.clear();
            return &result.value;
        }
        json& container = *stack_.back();
        if (container.is_array()) {
            lastPointer_ = pointers_.back() + "/" + std::to_string(container.size());
            container.push_back(std::move(value));
            return &container.back();
        }
        lastPointer_ = pointers_.back() + "/" + escapePointer(key_);
        json& slot = container[key_];
        slot = std::move(value);
        return &slot;
    }
    bool add(json value) {
        place(std::move(value));
        return true;
    }
    bool open(json container) {
        if (stack_.size() >= kMaxJsonDepth)
            return fail("the request nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        json* placed = place(std::move(container));
        stack_.push_back(placed);
        pointers_.push_back(lastPointer_);
        return true;
    }
    bool close() {
        stack_.pop_back();
        pointers_.pop_back();
        return true;
    }

    std::vector<json*> stack_;
    std::vector<std::string> pointers_;
    std::string key_, lastPointer_;
};

[[noreturn]] void wrongType(const std::string& what, const std::string& expected, const json& got,
                            const std::string& field = {}, const std::string& node = {}) {
    throw EditError(what + " takes " + expected + ", not " + quotedForMessage(got.dump(), 60), EditError::Kind::Type,
                    field, node);
}

// A number of `value` (not a boolean), and its text as typed.
double numberAt(const json& value, const TypedJson& request, const std::string& pointer, std::string& typed,
                const std::string& what, const std::string& expected, const std::string& field, const std::string& node) {
    if (!value.is_number()) wrongType(what, expected, value, field, node);
    auto text = request.typed.find(pointer);
    typed = text != request.typed.end() ? text->second : value.is_number_float() ? std::string() : value.dump();
    return value.get<double>();
}

std::vector<double> numbersAt(const json& value, size_t count, const TypedJson& request, const std::string& pointer,
                              std::vector<std::string>& typed, const std::string& what, const std::string& expected,
                              const std::string& field, const std::string& node) {
    if (!value.is_array() || value.size() != count) wrongType(what, expected, value, field, node);
    std::vector<double> numbers;
    for (size_t i = 0; i < count; ++i) {
        std::string text;
        numbers.push_back(numberAt(value[i], request, pointer + "/" + std::to_string(i), text, what, expected, field, node));
        typed.push_back(text);
    }
    return numbers;
}

TransformKind transformKind(const json& kind, const std::string& field, const std::string& node) {
    if (kind == "translate") return TransformKind::Translate;
    if (kind == "rotate") return TransformKind::Rotate;
    if (kind == "scale") return TransformKind::Scale;
    if (kind == "matrix") return TransformKind::Matrix;
    wrongType(field + "'s kind", "translate, rotate, scale or matrix", kind, field, node);
}

size_t transformNumbers(TransformKind kind) {
    return kind == TransformKind::Matrix ? 12 : kind == TransformKind::Rotate ? 4 : 3;
}

std::vector<TransformOp> transformsAt(const json& value, const TypedJson& request, const std::string& pointer,
                                      std::vector<std::string>& typed, const std::string& field,
                                      const std::string& node) {
    const std::string expected = "a list of transforms, each {\"kind\": translate|rotate|scale|matrix, \"v\": [...]}";
    if (!value.is_array()) wrongType(field, expected, value, field, node);
    std::vector<TransformOp> ops;
    for (size_t i = 0; i < value.size(); ++i) {
        const json& item = value[i];
        if (!item.is_object() || !item.contains("kind") || !item.contains("v") || item.size() != 2)
            wrongType(field, expected, item, field, node);
        TransformOp op;
        op.kind = transformKind(item["kind"], field, node);
        const size_t count = transformNumbers(op.kind);
        const std::vector<double> v =
            numbersAt(item["v"], count, request, pointer + "/" + std::to_string(i) + "/v", typed,
                      field + " " + std::to_string(i + 1) + " (" + item["kind"].get<std::string>() + ")",
                      std::to_string(count) + " numbers" +
                          (op.kind == TransformKind::Rotate ? " (the axis x, y, z and the angle in degrees)" : ""),
                      field, node);
        std::copy(v.begin(), v.end(), op.v.begin());
        ops.push_back(op);
    }
    return ops;
}

// ---------------------------------------------------------------------------------------
// Operations

std::string stringArgument(const json& request, const char* name, const char* op) {
    if (!request.contains(name)) throw EditError(std::string(op) + " needs \"" + name + "\"", EditError::Kind::Type, name);
    const json& value = request[name];
    if (!value.is_string()) wrongType(std::string(op) + "'s " + name, "a string", value, name);
    return value.get<std::string>();
}

NodeId nodeArgument(const json& value, const char* op, const char* name = "node") {
    if (!value.is_string()) wrongType(std::string(op) + "'s " + name, "a node id such as \"object-3\"", value, name);
    const std::string text = value.get<std::string>();
    std::optional<NodeId> id = NodeId::parse(text);
    if (!id)
        throw EditError(std::string(op) + "'s " + name + " '" + quotedForMessage(text, 60) +
                            "' names no node (ids are camera, globals, light-N, tree-N, block-N, object-N, "
                            "placement-N, csg-N)",
                        EditError::Kind::Value, name);
    return *id;
}

constexpr size_t kMaxNodesAnOperation = 10000;

std::vector<NodeId> nodesArgument(const json& request, const char* op) {
    if (request.contains("node") && !request.contains("nodes")) return {nodeArgument(request["node"], op)};
    if (!request.contains("nodes")) throw EditError(std::string(op) + " needs \"nodes\"", EditError::Kind::Type, "nodes");
    const json& nodes = request["nodes"];
    if (!nodes.is_array() || nodes.empty()) wrongType(std::string(op) + "'s nodes", "a list of node ids", nodes, "nodes");
    if (nodes.size() > kMaxNodesAnOperation)
        throw EditError(std::string(op) + " names " + std::to_string(nodes.size()) + " nodes; at most " +
                            std::to_string(kMaxNodesAnOperation) + " an operation",
                        EditError::Kind::Value, "nodes");
    std::vector<NodeId> ids;
    for (const json& node : nodes) ids.push_back(nodeArgument(node, op, "nodes"));
    return ids;
}

std::string fieldNames(FieldOwner owner) {
    std::string names;
    for (const EditField* field : fieldsOf(owner)) names += (names.empty() ? "" : ", ") + std::string(field->name);
    return names;
}

std::vector<FieldInput> fieldsArgument(const TypedJson& request, const json& fields, FieldOwner owner,
                                       const std::string& node) {
    if (!fields.is_object()) wrongType("fields", "an object of field names and values", fields, "fields", node);
    std::vector<FieldInput> inputs;
    for (const auto& [name, value] : fields.items()) {
        const EditField* field = findField(owner, name);
        if (!field)
            throw EditError(std::string("a ") + ownerName(owner) + " has no field '" + quotedForMessage(name, 60) +
                                "' (its fields: " + fieldNames(owner) + ")",
                            EditError::Kind::Value, quotedForMessage(name, 60), node);
        inputs.push_back(fieldInputFromJson(*field, value, request, "/fields/" + escapePointer(name), node));
    }
    return inputs;
}

void onlyKeys(const json& request, const char* op, std::initializer_list<std::string_view> keys) {
    for (const auto& [key, value] : request.items()) {
        bool known = key == "op" || key == "action";
        for (std::string_view k : keys) known = known || key == k;
        if (known) continue;
        std::string list;
        for (std::string_view k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
        throw EditError(std::string(op) + " takes " + (list.empty() ? "no arguments" : list) + ", not '" +
                            quotedForMessage(key, 60) + "'",
                        EditError::Kind::Value, quotedForMessage(key, 60));
    }
}

template <class Names, class Value>
Value choiceArgument(const json& request, const char* name, const char* op, const Names& names, Value first) {
    const std::string text = stringArgument(request, name, op);
    std::string list;
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i] == text) return Value(int(first) + int(i));
        list += (list.empty() ? "" : ", ") + std::string(names[i]);
    }
    throw EditError(std::string(op) + "'s " + name + " is one of " + list + ", not '" + quotedForMessage(text, 40) + "'",
                    EditError::Kind::Value, name);
}

PrimitiveType shapeArgument(const json& request) {
    static const PrimitiveType kShapes[] = {PrimitiveType::Cube, PrimitiveType::Cylinder, PrimitiveType::Cone,
                                            PrimitiveType::Sphere, PrimitiveType::Torus, PrimitiveType::Mesh};
    const int index = choiceArgument(request, "shape", "add-primitive", shapeNames(), 0);
    return kShapes[index];
}

SetFields cameraFromView(const Camera& view) {
    SetFields set{{NodeKind::Camera, 0}, {}};
    for (const auto& [name, value] : {std::pair<const char*, FieldValue>{"pos", view.position},
                                      {"look", view.look},
                                      {"up", view.up},
                                      {"heightangle", view.heightAngleDegrees}})
        set.fields.push_back({findField(FieldOwner::Camera, name), value, {}});
    return set;
}

std::string actionArgument(const json& request) {
    if (!request.contains("action")) return {};
    const json& action = request["action"];
    if (!action.is_string()) wrongType("action", "a string (the user action's id)", action, "action");
    const std::string text = action.get<std::string>();
    if (text.empty() || text.size() > kMaxActionLength)
        throw EditError("action is a string of 1 to " + std::to_string(kMaxActionLength) + " characters, not " +
                            std::to_string(text.size()),
                        EditError::Kind::Value, "action");
    for (unsigned char c : text)
        if (c < 0x20 || c == 0x7f)
            throw EditError("action holds a control character ('" + quotedForMessage(text, 40) + "')",
                            EditError::Kind::Value, "action");
    return text;
}

json numberJson(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }

}  // namespace

TypedJson parseTypedJson(std::string_view text) {
    if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) return {json::object(), {}};
    TypedParser parser;
    if (!json::sax_parse(text, &parser)) throw EditError(parser.error, EditError::Kind::Type);
    return std::move(parser.result);
}

FieldInput fieldInputFromJson(const EditField& field, const json& value, const TypedJson& request,
                              const std::string& pointer, const std::string& node) {
    const std::string name(field.name);
    FieldInput input{&field, 0.0, {}};
    switch (field.kind) {
        case FieldKind::Number: {
            std::string typed;
            input.value = numberAt(value, request, pointer, typed, name, "a number", name, node);
            input.typed = {typed};
            break;
        }
        case FieldKind::Color:
        case FieldKind::Vector: {
            const std::vector<double> v =
                numbersAt(value, 3, request, pointer, input.typed, name,
                          field.kind == FieldKind::Color ? "a color, three numbers [r, g, b]" : "three numbers [x, y, z]",
                          name, node);
            input.value = Vec3{v[0], v[1], v[2]};
            break;
        }
        case FieldKind::Choice:
        case FieldKind::Text:
        case FieldKind::File:
            if (!value.is_string()) wrongType(name, "a string", value, name, node);
            input.value = value.get<std::string>();
            break;
        case FieldKind::Transforms: input.value = transformsAt(value, request, pointer, input.typed, name, node); break;
        case FieldKind::Matrix: {
            const std::vector<double> v = numbersAt(value, 12, request, pointer, input.typed, name,
                                                    "twelve numbers, the matrix's first three rows", name, node);
            Affine m;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) m.m[r][c] = v[size_t(4 * r + c)];
            input.value = m;
            input.typed.clear();  // a dragged matrix is not typed
            break;
        }
    }
    return input;
}

JsonOperation operationFromJson(const TypedJson& typedRequest, const Camera* view) {
    const json& request = typedRequest.value;
    if (!request.is_object()) wrongType("an operation", "a JSON object {\"op\": ...}", request, "op");
    JsonOperation out{SetFields{}, actionArgument(request)};
    const std::string op = stringArgument(request, "op", "an operation");
    if (op == "set") {
        onlyKeys(request, "set", {"node", "fields"});
        if (!request.contains("node")) throw EditError("set needs \"node\"", EditError::Kind::Type, "node");
        const NodeId node = nodeArgument(request["node"], "set");
        const std::optional<FieldOwner> owner = fieldOwner(node.kind);
        if (!owner)
            throw EditError("a " + std::string(nodeKindName(node.kind)) + " has no fields to set", EditError::Kind::Value,
                            "node", node.text());
        if (!request.contains("fields")) throw EditError("set needs \"fields\"", EditError::Kind::Type, "fields");
        out.operation = SetFields{node, fieldsArgument(typedRequest, request["fields"], *owner, node.text())};
    } else if (op == "rename") {
        onlyKeys(request, "rename", {"node", "name"});
        const NodeId node = nodeArgument(request.value("node", json()), "rename");
        const json name = request.value("name", json());
        out.operation = SetFields{node, {fieldInputFromJson(*findField(FieldOwner::Tree, "name"), name, typedRequest,
                                                            "/name", node.text())}};
    } else if (op == "add-primitive") {
        onlyKeys(request, "add-primitive", {"shape", "file", "parent", "fields"});
        AddPrimitive add;
        add.shape = shapeArgument(request);
        if (request.contains("file")) add.meshFile = stringArgument(request, "file", "add-primitive");
        if (add.shape == PrimitiveType::Mesh && add.meshFile.empty())
            throw EditError("add-primitive of a mesh needs \"file\", an .obj in the scene's folder",
                            EditError::Kind::Value, "file");
        if (request.contains("parent")) add.parent = nodeArgument(request["parent"], "add-primitive", "parent");
        if (request.contains("fields"))
            add.fields = fieldsArgument(typedRequest, request["fields"], FieldOwner::Object, "");
        out.operation = std::move(add);
    } else if (op == "add-light") {
        onlyKeys(request, "add-light", {"type", "fields"});
        AddLight add;
        add.type = choiceArgument(request, "type", "add-light", lightTypeNames(), LightType::Point);
        if (request.contains("fields"))
            add.fields = fieldsArgument(typedRequest, request["fields"], FieldOwner::Light, "");
        out.operation = std::move(add);
    } else if (op == "delete") {
        onlyKeys(request, "delete", {"nodes", "node"});
        out.operation = DeleteNodes{nodesArgument(request, "delete")};
    } else if (op == "duplicate") {
        onlyKeys(request, "duplicate", {"nodes", "node"});
        out.operation = DuplicateNodes{nodesArgument(request, "duplicate")};
    } else if (op == "group") {
        onlyKeys(request, "group", {"nodes", "node"});
        out.operation = GroupNodes{nodesArgument(request, "group")};
    } else if (op == "make-unique") {
        onlyKeys(request, "make-unique", {"node"});
        out.operation = MakeUnique{nodeArgument(request.value("node", json()), "make-unique")};
    } else if (op == "camera-from-view") {
        onlyKeys(request, "camera-from-view", {});
        if (!view) throw EditError("camera-from-view: there is no view here; set the camera's fields instead");
        out.operation = cameraFromView(*view);
    } else {
        throw EditError("op is one of set, rename, add-primitive, add-light, delete, duplicate, group, make-unique, "
                        "camera-from-view or revert, not '" + quotedForMessage(op, 40) + "'",
                        EditError::Kind::Value, "op");
    }
    return out;
}

// ---------------------------------------------------------------------------------------
// Writing

json fieldValueJson(const FieldValue& value) {
    return std::visit(
        [](const auto& v) -> json {
            using V = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<V, double>) return numberJson(v);
            else if constexpr (std::is_same_v<V, Vec3>) return json::array({numberJson(v.x), numberJson(v.y), numberJson(v.z)});
            else if constexpr (std::is_same_v<V, std::string>) return v;
            else if constexpr (std::is_same_v<V, ImageHandle>) return json{{"image", v.index}};
            else if constexpr (std::is_same_v<V, Affine>) {
                json rows = json::array();
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 4; ++c) rows.push_back(numberJson(v.m[r][c]));
                return rows;
            } else {
                json ops = json::array();
                for (const TransformOp& op : v) {
                    static const char* const kKinds[] = {"translate", "rotate", "scale", "matrix"};
                    json numbers = json::array();
                    for (size_t k = 0; k < transformNumbers(op.kind); ++k) numbers.push_back(numberJson(op.v[k]));
                    ops.push_back({{"kind", kKinds[int(op.kind)]}, {"v", numbers}});
                }
                return ops;
            }
        },
        value);
}

json fieldTableJson() {
    json fields = json::array();
    for (const EditField& field : editFields()) {
        json entry{{"owner", ownerName(field.owner)}, {"group", field.group},      {"name", field.name},
                   {"keyword", field.keyword()},      {"kind", fieldKindName(field.kind)}, {"help", field.help}};
        if (const NumberRule* rule = field.rule) {
            if (std::isfinite(rule->low)) entry["min"] = rule->low;
            if (std::isfinite(rule->low) && !rule->lowIncluded) entry["min_excluded"] = true;
            if (std::isfinite(rule->high)) entry["max"] = rule->high;
            if (std::isfinite(rule->high) && !rule->highIncluded) entry["max_excluded"] = true;
        }
        if (field.nonzero) entry["nonzero"] = true;
        if (field.owner == FieldOwner::Light && field.lights != ~0u) {
            json lights = json::array();
            for (size_t t = 0; t < lightTypeNames().size(); ++t)
                if (field.appliesTo(LightType(t))) lights.push_back(lightTypeNames()[t]);
            entry["lights"] = lights;
        }
        if (!field.choices.empty()) entry["choices"] = field.choices;
        if (!field.extensions.empty()) entry["extensions"] = field.extensions;
        if (field.maxLength) entry["max_length"] = field.maxLength;
        fields.push_back(entry);
    }
    return {{"fields", fields}, {"shapes", shapeNames()}, {"light_types", lightTypeNames()}};
}

namespace {

json idsJson(const std::vector<NodeId>& ids) {
    json out = json::array();
    for (const NodeId& id : ids) out.push_back(id.text());
    return out;
}

json optionalId(const std::optional<NodeId>& id) { return id ? json(id->text()) : json(nullptr); }

json entryJson(const OutlineEntry& entry) {
    json out{{"node", entry.id.text()}, {"kind", nodeKindName(entry.id.kind)}, {"label", entry.label},
             {"text", entry.text},      {"path", entry.path},                  {"depth", entry.depth},
             {"parent", optionalId(entry.parent)}};
    if (!entry.shape.empty()) out["shape"] = entry.shape;
    if (!entry.type.empty()) out["type"] = entry.type;
    if (entry.id.kind == NodeKind::Tree) out["name"] = entry.name;
    if (entry.id.kind == NodeKind::Placement) out["master"] = optionalId(entry.master);
    return out;
}

}  // namespace

json outcomeJson(const Outcome& outcome) {
    return {{"changed", {{"tables", outcome.changes.names()}, {"nodes", idsJson(outcome.changed)}, {"outline", outcome.outline}}},
            {"added", idsJson(outcome.added)},
            {"removed", idsJson(outcome.removed)}};
}

json outlineJson(const std::vector<OutlineEntry>& entries) {
    json nodes = json::array();
    for (const OutlineEntry& entry : entries) nodes.push_back(entryJson(entry));
    return nodes;
}

json nodeJson(const NodeView& view) {
    json out = entryJson(view.entry);
    out.erase("depth");
    out["line"] = view.line;
    json fields = json::array();
    for (const auto& [field, value] : view.fields) fields.push_back({{"name", field->name}, {"value", fieldValueJson(value)}});
    out["fields"] = fields;
    if (view.entry.id.kind == NodeKind::Object) {
        out["instances"] = view.instances;
        out["master"] = optionalId(view.inMaster);
        out["own_block"] = view.ownBlock;
    }
    return out;
}

json errorJson(const EditError& error) {
    json out{{"error", error.what()}};
    if (!error.field.empty()) out["field"] = error.field;
    if (!error.node.empty()) out["node"] = error.node;
    if (error.kind == EditError::Kind::Exists) out["exists"] = true;
    return out;
}

}  // namespace ray::edit
