#include "viewer/viewer_session.h"

#include <stdexcept>

#include "core/message_text.h"
#include "explain/explanation_report.h"
#include "viewer/new_scene.h"

namespace ray {

using nlohmann::json;

namespace {

// The editor of the scene file, or of a new scene to be written there.
SceneEditor editorFor(const ViewerOptions& options) {
    if (options.newScene) return SceneEditor(options.scene, newSceneText(), options.load, options.historyLimit);
    return SceneEditor(options.scene, options.load, options.historyLimit);
}

}  // namespace

Session::Session(const ViewerOptions& options, std::unique_ptr<FrameSource> source)
    : options_(options), source_(std::move(source)), editor_(editorFor(options)) {
    scene_ = editor_.scene();
    sceneTime_ = lastWrite();
    view_ = {scene_->camera, options.settings};
}

void Session::start() {
    renderThread_ = std::thread([this] { renderLoop(); });
    watchThread_ = std::thread([this] { watchLoop(); });
}

void Session::stop() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        cancel_ = true;
        changed_.notify_all();
    }
    renderThread_.join();
    watchThread_.join();
}

json Session::state() {
    std::lock_guard lock(mutex_);
    json state = viewJson(view_);
    state.update(json{{"scene", options_.scene.filename().string()}, {"device", source_->deviceName()},
                      {"error", sceneError_}, {"view", requested_}, {"scene_version", sceneVersion_},
                      {"fit_window", options_.fitWindow}});
    state.update(editorStateLocked());
    return state;
}

uint64_t Session::request(const std::string& body) {
    std::lock_guard lock(mutex_);
    view_ = parseView(body, view_);
    newRequest();
    return requested_;
}

// Where "save scene" writes, whether there is something to undo or redo, the lights.
json Session::editorStateLocked() {
    return {{"file", std::filesystem::absolute(editor_.file()).lexically_normal().string()},
            {"modified", editor_.modified()}, {"can_undo", editor_.canUndo()},
            {"can_redo", editor_.canRedo()}, {"lights", editor_.lightsJson()},
            {"editable", !options_.token.empty()}, {"scene_version", sceneVersion_},
            {"revision", editor_.version()}, {"history", editor_.historyJson()}};
}

json Session::pick(int x, int y) {
    std::lock_guard lock(mutex_);
    return editor_.pick(view_.camera, view_.settings, x, y);
}

json Session::object(int id) {
    std::lock_guard lock(mutex_);
    return editor_.objectJson(id);
}

json Session::outline() {
    std::lock_guard lock(mutex_);
    json out = editor_.outlineJson();
    out["scene_version"] = sceneVersion_;
    return out;
}

json Session::node(const std::string& id) {
    std::lock_guard lock(mutex_);
    return editor_.nodeJson(id);
}

json Session::edit(const std::string& action, const std::string& body) {
    std::lock_guard lock(mutex_);
    edit::TypedJson request = edit::parseTypedJson(body);
    editor_.checkRevision(request.value);
    if (request.value.is_object()) request.value.erase("revision");  // checked; no part of the edit itself
    json out = json::object();
    if (action == "op") {
        out = editor_.operate(request, view_.camera);
    } else if (action == "edit") {
        editor_.edit(request);
        if (request.value.contains("object")) out["object"] = editor_.objectJson(request.value["object"].get<int>());
    } else if (action == "undo") {
        out = editor_.undo();
    } else if (action == "redo") {
        out = editor_.redo();
    } else if (action == "save") {
        const SaveRequest save = saveRequestFrom(request.value);
        const std::filesystem::path saved = editor_.save(save.as, save.replace, save.overwrite);
        // Its own save is not a change on disk to reload (which would clear the history).
        sceneTime_ = lastWrite();
        log("saved " + quotedForMessage(saved.string()));
        out["saved"] = saved.string();
    } else if (action == "reload") {
        // The user chose the file as it is on disk over the unsaved edits (a save refused
        // as the file changed there).
        sceneTime_ = lastWrite();
        editor_.reload();
        sceneError_.clear();
        log("reloaded " + quotedForMessage(editor_.file().filename().string()) + " (the unsaved edits were dropped)");
    }
    if (editor_.scene() != scene_) {
        scene_ = editor_.scene();
        ++sceneVersion_;
        newRequest();
    }
    const json state = editorStateLocked();
    out.update(state);  // the page of today reads them here
    out["editor"] = state;
    return out;
}

json Session::explain(int x, int y) {
    std::shared_ptr<const Scene> scene;
    View view;
    uint64_t viewId = 0, sceneVersion = 0;
    {
        std::lock_guard lock(mutex_);
        scene = scene_;
        view = view_;
        viewId = requested_;
        sceneVersion = sceneVersion_;
    }
    if (x < 0 || y < 0 || x >= view.settings.width || y >= view.settings.height)
        throw std::invalid_argument("pixel outside the image");
    Scene viewed = *scene;
    viewed.camera = view.camera;
    json tree = explanationJson(explainPixel(viewed, view.settings, x, y), viewed);
    tree["view"] = viewId;
    tree["scene_version"] = sceneVersion;
    return tree;
}

void Session::log(const std::string& message) const {
    if (options_.log) options_.log(message);
}

}  // namespace ray
