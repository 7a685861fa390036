#include "viewer/scene_editor.h"

#include "core/message_text.h"
#include "edit/field_table.h"
#include "edit/node_views.h"
#include "reference/reference_bvh.h"
#include "reference/reference_renderer.h"
#include "viewer/folder_files.h"

namespace ray {

namespace {

using nlohmann::json;
using edit::EditSession;
using edit::FieldOwner;
using edit::NodeId;
using edit::NodeKind;

// A file an edit names is one beside the scene (viewer/folder_files.h): no other folder,
// no link out of it.
edit::FileResolver confinedTo(const std::filesystem::path& sceneFile) {
    const std::filesystem::path folder = std::filesystem::absolute(sceneFile).parent_path();
    return [folder](const std::string& name, edit::FileUse use) {
        static const std::string_view kObj[] = {".obj"};
        const std::span<const std::string_view> extensions =
            use == edit::FileUse::Mesh ? std::span<const std::string_view>(kObj)
                                       : std::span<const std::string_view>(edit::findField(FieldOwner::Object, "texture")->extensions);
        return fileToRead(folder, name, use == edit::FileUse::Mesh ? "mesh" : "texture", extensions);
    };
}

edit::SessionOptions sessionOptions(const std::filesystem::path& file, const LoadOptions& options,
                                   size_t historyLimit) {
    return {options, true, confinedTo(file), historyLimit};
}

json vecJson(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

// The page of today's light fields: the table's, "attenuation" for the file's "function".
std::string tableName(const std::string& legacy) { return legacy == "attenuation" ? "function" : legacy; }

int wholeNumber(const json& value, const char* name) {
    if (!value.is_number_integer()) throw EditError(std::string(name) + " must be a whole number", EditError::Kind::Type, name);
    const int64_t n = value.get<int64_t>();
    if (n < 0 || n > INT32_MAX)
        throw EditError(std::string("there is no ") + name + " " + quotedForMessage(value.dump(), 30), EditError::Kind::Value, name);
    return int(n);
}

}  // namespace

// The file is stamped before it is read: changed while it is read, it differs from its
// stamp, and a save asks rather than replacing it.
SceneEditor::SceneEditor(const std::filesystem::path& file, const LoadOptions& options, size_t historyLimit)
    : file_(file), options_(options), stamp_(edit::stampOf(file)),
      session_(loadSceneDocument(file, options), sessionOptions(file, options, historyLimit)) {}

SceneEditor::SceneEditor(const std::filesystem::path& file, const std::string& text, const LoadOptions& options,
                         size_t historyLimit)
    : file_(file), options_(options), stamp_(edit::stampOf(file)),
      session_(loadSceneDocumentFromText(text, file, options), sessionOptions(file, options, historyLimit)) {
    session_.setModified();  // the file is written by the first save
}

StaleRevision::StaleRevision(uint64_t sent, uint64_t now)
    : std::runtime_error("the scene changed since this was sent (revision " + std::to_string(sent) + ", now " +
                         std::to_string(now) + ": another page's edit, or the file reloaded): nothing was done; "
                         "look at the scene as it is now and try again"),
      current(now) {}

void SceneEditor::checkRevision(const json& request) const {
    if (!request.is_object() || !request.contains("revision")) return;
    const json& sent = request["revision"];
    if (!sent.is_number_unsigned())
        throw EditError("revision must be a whole number (the scene's, from /state)", EditError::Kind::Type, "revision");
    if (sent.get<uint64_t>() != session_.version()) throw StaleRevision(sent.get<uint64_t>(), session_.version());
}

json SceneEditor::historyJson() const {
    return {{"bytes", session_.historyBytes()},
            {"limit", session_.historyLimit()},
            {"steps", session_.undoSteps() + session_.redoSteps()},
            {"dropped", session_.droppedSteps()}};
}

json SceneEditor::pick(const Camera& camera, const RenderSettings& settings, int x, int y) {
    if (x < 0 || y < 0 || x >= settings.width || y >= settings.height)
        throw EditError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                        std::to_string(settings.width) + "x" + std::to_string(settings.height) + " image");
    const std::shared_ptr<const Scene> scene = session_.scene();
    const reference::SceneIntersector intersector(*scene, reference::SceneSearch::Bvh, settings.courseMeshes);
    const std::optional<PickedSurface> hit = pickPixel(*scene, intersector, camera, settings, x, y);
    if (!hit) return {{"object", nullptr}, {"node", nullptr}, {"pixel", {x, y}}};
    const int id = scene->primitives[size_t(hit->primitive)].sourceObject;
    json out = id >= 0 ? objectJson(id) : json{{"object", nullptr}, {"node", nullptr}};
    out["instance"] = hit->primitive;
    out["point"] = vecJson(hit->point);
    out["normal"] = vecJson(hit->normal);
    out["distance"] = hit->distance;
    out["pixel"] = {x, y};
    return out;
}

json SceneEditor::outlineJson() {
    return {{"nodes", edit::outlineJson(session_.outline())}};
}

json SceneEditor::nodeJson(const std::string& id) {
    const std::optional<NodeId> node = NodeId::parse(id);
    if (!node)
        throw EditError("id '" + quotedForMessage(id, 60) + "' names no node (camera, globals, light-N, tree-N, block-N, "
                        "object-N, placement-N, csg-N)",
                        EditError::Kind::Value, "id");
    return edit::nodeJson(session_.describe(*node));
}

json SceneEditor::operate(const edit::TypedJson& request, const Camera& view) {
    if (request.value.is_object() && request.value.value("op", json()) == "revert") {
        const std::string action = request.value.value("action", json()).is_string() ? request.value["action"].get<std::string>() : "";
        const bool done = session_.revert(action);
        return {{"done", done}, {"changed", {{"tables", json::array()}, {"nodes", json::array()}, {"outline", done}}},
                {"added", json::array()}, {"removed", json::array()}};
    }
    const edit::JsonOperation operation = edit::operationFromJson(request, &view);
    return edit::outcomeJson(session_.apply(operation.operation, operation.action));
}

json SceneEditor::stepJson(const std::optional<edit::Outcome>& outcome) {
    json out = outcome ? edit::outcomeJson(*outcome) : edit::outcomeJson({});
    out["done"] = outcome.has_value();
    return out;
}

json SceneEditor::undo() { return stepJson(session_.undo()); }
json SceneEditor::redo() { return stepJson(session_.redo()); }

json SceneEditor::objectJson(int id) {
    const json node = nodeJson(NodeId{NodeKind::Object, id}.text());
    json material = json::object(), transform = json::array();
    for (const json& field : node["fields"]) {
        const edit::EditField* f = edit::findField(FieldOwner::Object, field["name"].get<std::string>());
        if (f->group == "material") material[field["name"].get<std::string>()] = field["value"];
        if (f->special == edit::SpecialField::Transforms) transform = field["value"];
    }
    return {{"object", id},          {"node", node["node"]},  {"type", node["shape"]},
            {"path", node["path"]},  {"line", node["line"]},  {"material", material},
            {"transform", transform}, {"block_objects", 1},   {"instances", node["instances"]},
            {"own_block", node["own_block"]}};
}

json SceneEditor::lightsJson() {
    json lights = json::array();
    const SceneDocument& document = session_.document();
    for (size_t i = 0; i < document.lights.size(); ++i) {
        const Light& l = document.lights[i];
        lights.push_back({{"index", i},
                          {"node", NodeId{NodeKind::Light, document.lightIds[i]}.text()},
                          {"type", lightTypeName(l.type)},
                          {"color", vecJson(l.color)},
                          {"position", vecJson(l.position)},
                          {"direction", vecJson(l.direction)},
                          {"attenuation", vecJson(l.attenuation)},
                          {"angle", l.angleDegrees},
                          {"penumbra", l.penumbraDegrees},
                          {"width", l.width},
                          {"height", l.height}});
    }
    return lights;
}

// The page of today's edits as operations of the edit model: the same checks, the same
// meaning (a transform edit moves the object), one step each.
void SceneEditor::edit(const edit::TypedJson& request) {
    const json& body = request.value;
    if (!body.is_object()) throw EditError("an edit must be a JSON object", EditError::Kind::Type);
    edit::SetFields set;
    if (body.contains("object")) {
        set.node = {NodeKind::Object, wholeNumber(body["object"], "object")};
        const bool material = body.contains("material"), transform = body.contains("transform");
        if (material == transform) throw EditError("an object's edit sets its material or its transform (one of them)");
        if (material) {
            const json& fields = body["material"];
            if (!fields.is_object() || fields.empty())
                throw EditError("material must be an object of fields to set", EditError::Kind::Type, "material");
            for (const auto& [name, value] : fields.items()) {
                const edit::EditField* field = edit::findField(FieldOwner::Object, name);
                if (!field || field->group != "material")
                    throw EditError("a material has no field '" + quotedForMessage(name, 60) + "'", EditError::Kind::Value,
                                    quotedForMessage(name, 60), set.node.text());
                set.fields.push_back(edit::fieldInputFromJson(*field, value, request, "/material/" + name, set.node.text()));
            }
        } else {
            set.fields.push_back(edit::fieldInputFromJson(*edit::findField(FieldOwner::Object, "transform"),
                                                          body["transform"], request, "/transform", set.node.text()));
        }
    } else if (body.contains("light")) {
        const int index = wholeNumber(body["light"], "light");
        const SceneDocument& document = session_.document();
        if (size_t(index) >= document.lights.size())
            throw EditError("there is no light " + std::to_string(index) + " (the scene has " +
                            std::to_string(document.lights.size()) + ")", EditError::Kind::Value, "light");
        set.node = {NodeKind::Light, document.lightIds[size_t(index)]};
        for (const auto& [name, value] : body.items()) {
            if (name == "light") continue;
            const edit::EditField* field = edit::findField(FieldOwner::Light, tableName(name));
            if (!field || field->special != edit::SpecialField::None)
                throw EditError("a light has no field '" + quotedForMessage(name, 60) + "' that can be edited here",
                                EditError::Kind::Value, quotedForMessage(name, 60), set.node.text());
            set.fields.push_back(edit::fieldInputFromJson(*field, value, request, "/" + name, set.node.text()));
        }
    } else {
        throw EditError("an edit names an \"object\" (its id) or a \"light\" (its index)");
    }
    session_.apply(set);
}

SaveRequest saveRequestFrom(const nlohmann::json& request) {
    SaveRequest save;
    if (!request.is_object()) throw EditError("save: the request is a JSON object, {} or {\"as\": \"other.xml\"}");
    if (request.contains("as")) {
        if (!request["as"].is_string()) throw EditError("save as: the name must be a string", EditError::Kind::Type, "as");
        save.as = request["as"].get<std::string>();
    }
    for (auto [name, flag] : {std::pair{"replace", &save.replace}, std::pair{"overwrite", &save.overwrite}}) {
        if (!request.contains(name)) continue;
        if (!request[name].is_boolean())
            throw EditError(std::string("save: ") + name + " is true or false", EditError::Kind::Type, name);
        *flag = request[name].get<bool>();
    }
    return save;
}

std::filesystem::path SceneEditor::save(const std::optional<std::string>& as, bool replace, bool overwrite) {
    const std::filesystem::path own = std::filesystem::absolute(file_).lexically_normal();
    std::filesystem::path target = own;
    std::error_code ec;
    if (as) {
        // The name says the format (saveDocument): .json writes the course's JSON, .xml XML.
        static constexpr std::string_view kXmlFirst[] = {".xml", ".json"}, kJsonFirst[] = {".json", ".xml"};
        const bool json = session_.document().format == SceneFormat::Json;
        target = fileInFolder(own.parent_path(), *as, "save as", json ? std::span(kJsonFirst) : std::span(kXmlFirst));
        if (!std::filesystem::equivalent(target, own, ec)) checkMayWrite(target, replace, "save as");
    }
    const bool ownFile = target == own || std::filesystem::equivalent(target, own, ec);
    if (ownFile && !overwrite) {
        if (const std::optional<std::string> change = edit::changeSince(stamp_, own))
            throw ChangedOnDisk(own.filename().string() + " " + *change +
                                ": not saved, so that its change is not lost; overwrite it with this scene, or load "
                                "it again (this scene's unsaved edits are then lost)");
    }
    try {
        saveDocument(session_.document(), session_.resources(), target);
    } catch (const InputError& e) {
        throw EditError(std::string("not saved: ") + e.what());
    }
    if (ownFile) {
        stamp_ = edit::stampOf(own);
        session_.saved();
    }
    return target;
}

std::string SceneEditor::documentText() const {
    std::filesystem::path target = file_;
    if (session_.document().format == SceneFormat::Xml) target.replace_extension(".xml");
    return documentToText(session_.document(), session_.resources(), target);
}

void SceneEditor::reload() {
    const edit::FileStamp stamp = edit::stampOf(file_);
    reload(loadSceneDocument(file_, options_), Resources{}, stamp);
}

void SceneEditor::reload(SceneDocument document, Resources resources, const edit::FileStamp& stamp) {
    session_.reload(std::move(document), std::move(resources));
    stamp_ = stamp;
}

}  // namespace ray
