#include "viewer/viewer_session.h"

#include <stdexcept>

#include "core/message_text.h"
#include "explain/explanation_report.h"
#include "viewer/new_scene.h"
#include "viewer/stop_signals.h"

namespace ray {

using nlohmann::json;

namespace {

// The editor of the scene file, of a recovery's edits to it (--recover: unsaved until
// saved), or of a new scene to be written there.
SceneEditor editorFor(const ViewerOptions& options) {
    if (options.recovered) {
        try {
            return SceneEditor(options.scene, options.recovered->document, options.load, options.historyLimit);
        } catch (const InputError& e) {
            // Its lines are the kept text's, which the message must say.
            throw InputError(std::string(e.what()) + "\n(in the unsaved edits kept in " +
                             quotedForMessage(options.recovered->file.string()) +
                             ", which do not load: open the scene without --recover, or remove that file)");
        }
    }
    if (options.newScene) return SceneEditor(options.scene, newSceneText(options.scene), options.load, options.historyLimit);
    return SceneEditor(options.scene, options.load, options.historyLimit);
}

// An offer without its document, which the page never needs (restoring reads the file again).
std::optional<Recovery> withoutDocument(std::optional<Recovery> recovery) {
    if (recovery) std::string().swap(recovery->document);
    return recovery;
}

}  // namespace

Session::Session(const ViewerOptions& options, std::unique_ptr<FrameSource> source)
    : options_(options), source_(std::move(source)), editor_(editorFor(options)),
      edited_(options.recovered.has_value()), offer_(withoutDocument(options.offer)) {
    scene_ = editor_.scene();
    sceneStamp_ = stampOf(options_.scene);
    for (const std::filesystem::path& file : resourceFilesLocked()) fileStamps_[file] = stampOf(file);
    view_ = {scene_->camera, options.settings};
    if (!options.recoveryFolder.empty())
        keeper_ = std::make_unique<RecoveryKeeper>(options.recoveryFolder, options.scene,
                                                   [this] { return unsavedDocument(); },
                                                   [this](const std::string& message) { log(message); });
}

void Session::start() {
    renderThread_ = std::thread([this] { renderLoop(); });
    watchThread_ = std::thread([this] { watchLoop(); });
    if (keeper_ && options_.recovered) {
        // The restored edits are this viewer's now: its own copy replaces the one it read.
        keeper_->replaces(options_.recovered->file);
        keeper_->changed(true);
    }
    if (options_.onStopSignal)
        StopSignals::beforeExit([this](int signal) {
            options_.onStopSignal(signal, keeper_ ? keeper_->keepNow() : RecoveryKeeper::Kept{});
        });
}

void Session::stop() {
    if (options_.onStopSignal) StopSignals::beforeExit(nullptr);
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        cancel_ = true;
        changed_.notify_all();
    }
    renderThread_.join();
    watchThread_.join();
    if (keeper_) keeper_->stop();
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

// Where "save scene" writes and in which format, whether there is something to undo or redo, the lights.
json Session::editorStateLocked() {
    return {{"file", std::filesystem::absolute(editor_.file()).lexically_normal().string()},
            {"format", editor_.formatName()},      {"modified", editor_.modified()}, {"can_undo", editor_.canUndo()},
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
    if (action == "recovery") return answerRecovery(body);  // reads files: not under the lock
    if (action == "reload") return reloadOnRequest(body);    // the same
    std::lock_guard lock(mutex_);
    const uint64_t versionBefore = editor_.version();
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
        sceneStamp_ = stampOf(options_.scene);
        ++saves_;
        log("saved " + quotedForMessage(saved.string()));
        out["saved"] = saved.string();
        if (keeper_) keeper_->sceneRead();
        documentChangedLocked(true);  // saved: the copy goes at once
    }
    if (editor_.version() != versionBefore) {
        edited_ = true;
        documentChangedLocked(false);
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

// POST /reload: the user takes the file as it is on disk over the unsaved edits (a save
// refused as another program changed it). Read as the watch reads it, outside the lock; the
// edits it replaces are set aside as a recovery, as the watch's reload does.
json Session::reloadOnRequest(const std::string& body) {
    uint64_t saves = 0;
    {
        std::lock_guard lock(mutex_);
        editor_.checkRevision(edit::parseTypedJson(body).value);
        saves = saves_;
    }
    reloadScene(stampOf(options_.scene), saves);
    std::lock_guard lock(mutex_);
    if (editor_.modified())
        throw EditError("not reloaded: " + (sceneError_.empty() ? std::string("the scene was saved meanwhile") : sceneError_));
    const json state = editorStateLocked();
    json out = state;
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

// ---- Unsaved edits kept (viewer/recovery.h)

std::optional<std::string> Session::unsavedDocument() {
    std::lock_guard lock(mutex_);
    if (!edited_ || !editor_.modified()) return std::nullopt;
    try {
        return editor_.documentText();
    } catch (const std::exception& e) {
        throw RecoveryError(std::string("the scene's text could not be made: ") + e.what());
    }
}

void Session::documentChangedLocked(bool now) {
    if (keeper_) keeper_->changed(now);
}

std::optional<Recovery> Session::nextOffer(const std::filesystem::path& answered) const {
    if (options_.recoveryFolder.empty()) return std::nullopt;
    for (Recovery& recovery : findRecoveries(options_.recoveryFolder, options_.scene, nullptr,
                                             keeper_ ? keeper_->file() : std::filesystem::path()))
        if (recovery.file != answered) return withoutDocument(std::move(recovery));
    return std::nullopt;
}

json Session::recoveryOffer() {
    std::optional<Recovery> offer;
    {
        std::lock_guard lock(mutex_);
        offer = offer_;
    }
    if (!offer) return {{"offer", nullptr}};
    // Outside the lock: this reads the scene file.
    return {{"offer",
             {{"file", offer->file.string()},
              {"scene", offer->scene},
              {"written", offer->writtenText},
              {"scene_changed", sceneChangedSince(*offer, options_.scene)},
              {"command", "ray view " + options_.scene.string() + " --recover"}}}};
}

json Session::answerRecovery(const std::string& body) {
    const json request = edit::parseTypedJson(body).value;
    if (!request.is_object() || !request.contains("action") || !request["action"].is_string())
        throw EditError("a recovery answer is {\"action\": \"restore\"} or {\"action\": \"discard\"}", EditError::Kind::Type,
                        "action");
    const std::string action = request["action"].get<std::string>();
    if (action != "restore" && action != "discard")
        throw EditError("a recovery's action is \"restore\" or \"discard\", not '" + quotedForMessage(action, 40) + "'",
                        EditError::Kind::Value, "action");
    std::filesystem::path file;
    {
        std::lock_guard lock(mutex_);
        if (!offer_) throw EditError("there is no recovery of this scene to " + action, EditError::Kind::Value, "action");
        file = offer_->file;
    }
    if (request.contains("file") && request["file"] != file.string())
        throw EditError("the recovery offered is now " + quotedForMessage(file.string()) + ": reload the page",
                        EditError::Kind::Exists, "file");
    return action == "restore" ? restoreRecovery(file) : discardRecovery(file);
}

json Session::restoreRecovery(const std::filesystem::path& file) {
    const auto refuseOwnEdits = [this] {
        if (edited_ && editor_.modified())
            throw EditError("this viewer has unsaved edits of its own: save them (or undo them) before restoring "
                            "another's", EditError::Kind::Exists, "action");
    };
    {
        std::lock_guard lock(mutex_);
        refuseOwnEdits();
    }
    // Read and loaded outside the lock: the view goes on meanwhile.
    std::optional<SceneEditor> restored;
    try {
        restored.emplace(options_.scene, readRecovery(file).document, options_.load);
    } catch (const std::exception& e) {
        throw EditError(std::string("the recovery cannot be restored: ") + e.what());
    }
    std::optional<Recovery> next = nextOffer(file);
    std::lock_guard lock(mutex_);
    refuseOwnEdits();
    editor_ = std::move(*restored);
    edited_ = true;
    offer_ = std::move(next);
    scene_ = editor_.scene();
    ++sceneVersion_;
    newRequest();
    log("restored the unsaved edits of " + quotedForMessage(file.string()) + " (not saved yet)");
    if (keeper_) {
        keeper_->replaces(file);
        keeper_->changed(true);
    }
    json out = editorStateLocked();
    out["restored"] = file.string();
    out["editor"] = editorStateLocked();
    return out;
}

json Session::discardRecovery(const std::filesystem::path& file) {
    try {
        removeRecovery(file);
    } catch (const RecoveryError& e) {
        throw EditError(e.what());
    }
    std::optional<Recovery> next = nextOffer(file);
    log("discarded the unsaved edits of " + quotedForMessage(file.string()));
    std::lock_guard lock(mutex_);
    offer_ = std::move(next);
    json out = editorStateLocked();
    out["discarded"] = file.string();
    out["editor"] = editorStateLocked();
    return out;
}

void Session::log(const std::string& message) const {
    if (options_.log) options_.log(message);
}

}  // namespace ray
