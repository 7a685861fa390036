#include "viewer/scene_editor.h"

#include <cmath>
#include <variant>

#include "reference/reference_bvh.h"
#include "reference/reference_renderer.h"
#include "scene/parameter_rules.h"
#include "viewer/folder_files.h"

namespace ray {

namespace {

using nlohmann::json;

// Successive edits of one thing within this long are one step of the history.
constexpr auto kMergeEdits = std::chrono::milliseconds(1500);
constexpr size_t kHistory = 200;
constexpr size_t kMaxTransforms = 16;

json vecJson(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

double numberFrom(const json& j, const std::string& name) {
    if (!j.is_number()) throw EditError(name + " must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) throw EditError(name + " must be a finite number");
    return v;
}

Vec3 vecFrom(const json& j, const std::string& name) {
    if (!j.is_array() || j.size() != 3) throw EditError(name + " must be [x, y, z]");
    return {numberFrom(j[0], name), numberFrom(j[1], name), numberFrom(j[2], name)};
}

void check(const std::optional<RuleBroken>& broken) {
    if (broken) throw EditError(broken->sentence());
}

Vec3 colorFrom(const json& j, const std::string& name) {
    Vec3 c = vecFrom(j, name);
    check(brokenRule(name, c, rules::kColorChannel));
    return c;
}

const char* kindName(TransformKind kind) {
    switch (kind) {
        case TransformKind::Translate: return "translate";
        case TransformKind::Rotate: return "rotate";
        case TransformKind::Scale: return "scale";
        case TransformKind::Matrix: return "matrix";
    }
    return "?";
}

size_t valueCount(TransformKind kind) {
    return kind == TransformKind::Matrix ? 12 : kind == TransformKind::Rotate ? 4 : 3;
}

json materialJson(const Material& m) {
    return {{"diffuse", vecJson(m.diffuse)},         {"ambient", vecJson(m.ambient)},
            {"specular", vecJson(m.specular)},       {"reflective", vecJson(m.reflective)},
            {"transparent", vecJson(m.transparent)}, {"emissive", vecJson(m.emissive)},
            {"shininess", m.shininess},              {"ior", m.ior},
            {"blend", m.blend}};
}

void editMaterial(Material& m, const json& j) {
    if (!j.is_object() || j.empty()) throw EditError("material must be an object of fields to set");
    for (const auto& [key, value] : j.items()) {
        if (key == "diffuse") m.diffuse = colorFrom(value, key);
        else if (key == "ambient") m.ambient = colorFrom(value, key);
        else if (key == "specular") m.specular = colorFrom(value, key);
        else if (key == "reflective") m.reflective = colorFrom(value, key);
        else if (key == "transparent") m.transparent = colorFrom(value, key);
        else if (key == "emissive") m.emissive = colorFrom(value, key);
        else if (key == "shininess") check(brokenRule(key, m.shininess = numberFrom(value, key), rules::kShininess));
        else if (key == "ior") check(brokenRule(key, m.ior = numberFrom(value, key), rules::kIor));
        else if (key == "blend") check(brokenRule(key, m.blend = numberFrom(value, key), rules::kBlend));
        else throw EditError("a material has no field '" + key + "' (diffuse, ambient, specular, reflective, "
                             "transparent, emissive, shininess, ior, blend)");
    }
}

std::vector<TransformOp> transformsFrom(const json& j) {
    if (!j.is_array()) throw EditError("transform must be a list of {\"kind\", \"v\"}");
    if (j.size() > kMaxTransforms) throw EditError("a transblock may hold at most 16 transforms here");
    std::vector<TransformOp> ops;
    for (const json& item : j) {
        if (!item.is_object() || !item.contains("kind") || !item["kind"].is_string() || !item.contains("v"))
            throw EditError("each transform must be {\"kind\": translate|rotate|scale|matrix, \"v\": [...]}");
        const std::string kind = item["kind"];
        TransformOp op;
        if (kind == "translate") op.kind = TransformKind::Translate;
        else if (kind == "rotate") op.kind = TransformKind::Rotate;
        else if (kind == "scale") op.kind = TransformKind::Scale;
        else if (kind == "matrix") op.kind = TransformKind::Matrix;
        else throw EditError("a transform's kind is translate, rotate, scale or matrix, not '" + kind + "'");
        const json& v = item["v"];
        const size_t n = valueCount(op.kind);
        if (!v.is_array() || v.size() != n)
            throw EditError(kind + " takes " + std::to_string(n) + " numbers" +
                            (op.kind == TransformKind::Rotate ? " (the axis x, y, z and the angle in degrees)" : ""));
        for (size_t i = 0; i < n; ++i) op.v[i] = numberFrom(v[i], kind);
        if (auto why = op.whySingular()) throw EditError(kind + ": " + *why + "; it must be invertible");
        ops.push_back(op);
    }
    return ops;
}

json lightJson(const Light& l, size_t index) {
    static const char* const kTypes[] = {"point", "directional", "spot", "area"};
    return {{"index", index},
            {"type", kTypes[int(l.type)]},
            {"color", vecJson(l.color)},
            {"position", vecJson(l.position)},
            {"direction", vecJson(l.direction)},
            {"attenuation", vecJson(l.attenuation)},
            {"angle", l.angleDegrees},
            {"penumbra", l.penumbraDegrees},
            {"width", l.width},
            {"height", l.height}};
}

void editLight(Light& l, const json& j) {
    for (const auto& [key, value] : j.items()) {
        if (key == "light") continue;
        if (key == "color") l.color = colorFrom(value, key);
        else if (key == "position") l.position = vecFrom(value, key);
        else if (key == "direction") {
            l.direction = vecFrom(value, key);
            if (length(l.direction) == 0) throw EditError("a light's direction must not be (0, 0, 0)");
        } else if (key == "attenuation") check(brokenRule(key, l.attenuation = vecFrom(value, key), rules::kAttenuation));
        else if (key == "angle") check(brokenRule(key, l.angleDegrees = numberFrom(value, key), rules::kSpotAngle));
        else if (key == "penumbra") check(brokenRule(key, l.penumbraDegrees = numberFrom(value, key), rules::kPenumbra));
        else if (key == "width") check(brokenRule(key, l.width = numberFrom(value, key), rules::kAreaSide));
        else if (key == "height") check(brokenRule(key, l.height = numberFrom(value, key), rules::kAreaSide));
        else throw EditError("a light has no field '" + key + "' that can be edited here (color, position, direction, "
                             "attenuation, angle, penumbra, width, height)");
    }
    if (l.attenuation == Vec3{0, 0, 0}) throw EditError("attenuation (0, 0, 0) divides by zero; make c1, c2 or c3 positive");
}

int intFrom(const json& j, const std::string& name) {
    if (!j.is_number_integer()) throw EditError(name + " must be a whole number");
    return j.get<int>();
}

}  // namespace

SceneEditor::SceneEditor(const std::filesystem::path& file, const LoadOptions& options)
    : file_(file), options_(options) {
    document_ = loadSceneDocument(file_, options_);
    scene_ = flatten(document_);
}

SceneEditor::SceneEditor(const std::filesystem::path& file, const std::string& text, const LoadOptions& options)
    : file_(file), options_(options) {
    document_ = loadSceneDocumentFromText(text, file_, options_);
    scene_ = flatten(document_);
    modified_ = true;  // the file is written by the first save
}

std::shared_ptr<const Scene> SceneEditor::flatten(SceneDocument& document) {
    return std::make_shared<const Scene>(flattenDocument(document, resources_, options_));
}

json SceneEditor::pick(const Camera& camera, const RenderSettings& settings, int x, int y) const {
    if (x < 0 || y < 0 || x >= settings.width || y >= settings.height)
        throw EditError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                        std::to_string(settings.width) + "x" + std::to_string(settings.height) + " image");
    const reference::SceneIntersector intersector(*scene_, reference::SceneSearch::Bvh, settings.courseMeshes);
    const std::optional<PickedSurface> hit = pickPixel(*scene_, intersector, camera, settings, x, y);
    if (!hit) return {{"object", nullptr}, {"pixel", {x, y}}};
    const int id = scene_->primitives[size_t(hit->primitive)].sourceObject;
    json out = id >= 0 ? objectJson(id) : json{{"object", nullptr}};
    out["instance"] = hit->primitive;
    out["point"] = vecJson(hit->point);
    out["normal"] = vecJson(hit->normal);
    out["distance"] = hit->distance;
    out["pixel"] = {x, y};
    return out;
}

json SceneEditor::objectJson(int id) const {
    std::optional<DocumentPlace> place = findObject(document_, id);
    if (!place) throw EditError("there is no object " + std::to_string(id));
    const PrimitiveNode& node = std::get<PrimitiveNode>(place->block->items[place->item]);
    json transforms = json::array();
    for (const TransformOp& op : place->block->transforms)
        transforms.push_back({{"kind", kindName(op.kind)},
                              {"v", std::vector<double>(op.v.begin(), op.v.begin() + long(valueCount(op.kind)))}});
    size_t objects = 0, instances = 0;
    for (const SceneItem& item : place->block->items) objects += std::holds_alternative<PrimitiveNode>(item) ? 1 : 0;
    for (const PrimitiveInstance& p : scene_->primitives) instances += p.sourceObject == id ? 1 : 0;
    return {{"object", id},
            {"type", primitiveTypeName(node.type)},
            {"path", place->path},
            {"line", node.line},
            {"material", materialJson(node.material)},
            {"transform", transforms},
            {"block_items", place->block->items.size()},
            {"block_objects", objects},
            {"instances", instances}};
}

json SceneEditor::lightsJson() const {
    json lights = json::array();
    for (size_t i = 0; i < document_.lights.size(); ++i) lights.push_back(lightJson(document_.lights[i], i));
    return lights;
}

void SceneEditor::edit(const json& request) {
    if (!request.is_object()) throw EditError("an edit must be a JSON object");
    SceneDocument edited = document_;
    std::string key;
    if (request.contains("object")) {
        const int id = intFrom(request["object"], "object");
        std::optional<DocumentPlace> place = findObject(edited, id);
        if (!place) throw EditError("there is no object " + std::to_string(id));
        const bool material = request.contains("material"), transform = request.contains("transform");
        if (material == transform) throw EditError("an object's edit sets its material or its transform (one of them)");
        if (material) {
            editMaterial(std::get<PrimitiveNode>(place->block->items[place->item]).material, request["material"]);
            key = "object " + std::to_string(id) + " material";
        } else {
            place->block->transforms = transformsFrom(request["transform"]);
            composeBlock(*place->block);
            key = "object " + std::to_string(id) + " transform";
        }
    } else if (request.contains("light")) {
        const int index = intFrom(request["light"], "light");
        if (index < 0 || size_t(index) >= edited.lights.size())
            throw EditError("there is no light " + std::to_string(index) + " (the scene has " +
                            std::to_string(edited.lights.size()) + ")");
        editLight(edited.lights[size_t(index)], request);
        key = "light " + std::to_string(index);
    } else {
        throw EditError("an edit names an \"object\" (its id) or a \"light\" (its index)");
    }
    apply(std::move(edited), key);
}

void SceneEditor::apply(SceneDocument document, const std::string& key) {
    std::shared_ptr<const Scene> scene;
    try {
        scene = flatten(document);
    } catch (const std::exception& e) {
        throw EditError(std::string("the edit was not made: ") + e.what());
    }
    const auto now = std::chrono::steady_clock::now();
    const bool merge = !undo_.empty() && key == lastKey_ && now - lastEditAt_ < kMergeEdits;
    if (!merge) {
        undo_.push_back({std::move(document_), modified_});
        if (undo_.size() > kHistory) undo_.erase(undo_.begin());
    }
    document_ = std::move(document);
    scene_ = std::move(scene);
    redo_.clear();
    lastKey_ = key;
    lastEditAt_ = now;
    modified_ = true;
    ++version_;
}

bool SceneEditor::undo() {
    if (undo_.empty()) return false;
    State state = std::move(undo_.back());
    undo_.pop_back();
    scene_ = flatten(state.document);
    redo_.push_back({std::move(document_), modified_});
    document_ = std::move(state.document);
    modified_ = state.modified;
    lastKey_.clear();
    ++version_;
    return true;
}

bool SceneEditor::redo() {
    if (redo_.empty()) return false;
    State state = std::move(redo_.back());
    redo_.pop_back();
    scene_ = flatten(state.document);
    undo_.push_back({std::move(document_), modified_});
    document_ = std::move(state.document);
    modified_ = state.modified;
    lastKey_.clear();
    ++version_;
    return true;
}

SaveRequest saveRequestFrom(const nlohmann::json& request) {
    SaveRequest save;
    if (!request.is_object()) throw EditError("save: the request is a JSON object, {} or {\"as\": \"other.xml\"}");
    if (request.contains("as")) {
        if (!request["as"].is_string()) throw EditError("save as: the name must be a string");
        save.as = request["as"].get<std::string>();
    }
    if (request.contains("replace")) {
        if (!request["replace"].is_boolean()) throw EditError("save: replace is true or false");
        save.replace = request["replace"].get<bool>();
    }
    return save;
}

std::filesystem::path SceneEditor::save(const std::optional<std::string>& as, bool replace) {
    const std::filesystem::path own = std::filesystem::absolute(file_).lexically_normal();
    std::filesystem::path target = own;
    if (as) {
        target = fileInFolder(own.parent_path(), *as, "save as", {".xml"});
        std::error_code ec;
        if (!std::filesystem::equivalent(target, own, ec)) checkMayWrite(target, replace, "save as");
    }
    try {
        saveDocument(document_, resources_, target);
    } catch (const InputError& e) {
        throw EditError(std::string("not saved: ") + e.what());
    }
    std::error_code ec;
    if (std::filesystem::equivalent(target, own, ec)) {
        modified_ = false;
        for (State& s : undo_) s.modified = true;  // each differs from the file now written
        for (State& s : redo_) s.modified = true;
    }
    lastKey_.clear();  // the next edit is a step of its own
    return target;
}

void SceneEditor::reload() {
    SceneDocument document = loadSceneDocument(file_, options_);
    Resources resources;
    auto scene = std::make_shared<const Scene>(flattenDocument(document, resources, options_));
    document_ = std::move(document);
    resources_ = std::move(resources);
    scene_ = std::move(scene);
    undo_.clear();
    redo_.clear();
    lastKey_.clear();
    modified_ = false;
    ++version_;
}

}  // namespace ray
