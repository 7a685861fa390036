// What `ray view` edits: the editing service (edit/edit_session.h) over the file it opened,
// spoken in the page's JSON (docs/modeler-protocol.md): the field table, the outline, a
// node's fields, operations with their action ids, undo and redo, and saving into the
// scene's folder. The page, the C++ API and Python edit through the same service, with the
// same operations and fields. Kept apart from the HTTP server so that tests drive it
// directly.
//
// Every edit is checked whole before anything changes: a refused one throws EditError (a
// sentence naming the field) and leaves the document, its history and the scene as they
// were. One user action is one step of the history (the operations carrying its action id:
// a drag), however quick or slow.
//
// POST /edit and GET /object, the page's routes before the edit model, are kept here as
// translations onto the same operations until the studio page has moved to /op and /node.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "edit/edit_error.h"
#include "edit/edit_json.h"
#include "edit/edit_session.h"
#include "edit/file_stamp.h"
#include "render/render_settings.h"
#include "scene/scene.h"
#include "scene/scene_document.h"
#include "scene/scene_loader.h"

namespace ray {

using EditError = edit::EditError;

// What POST /save asks: {"as": name} (absent: the file the editor opened),
// {"replace": true} to replace an existing file, and {"overwrite": true} to replace the
// opened file although another program changed it since it was read (ChangedOnDisk).
struct SaveRequest {
    std::optional<std::string> as;
    bool replace = false;
    bool overwrite = false;
};
// Throws EditError when a field has the wrong type.
SaveRequest saveRequestFrom(const nlohmann::json& request);

// An edit, undo, redo or save made against another revision of the scene than the one it
// has now (another page edited it, the file was reloaded): refused, 409, with the current
// state, so that the page shows what is there before the user acts again.
struct StaleRevision : std::runtime_error {
    StaleRevision(uint64_t sent, uint64_t current);
    uint64_t current;
};

// A save that would replace the opened file, which another program changed since the
// editor read or wrote it: refused, 409, until the user says to overwrite it (or reloads).
struct ChangedOnDisk : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class SceneEditor {
public:
    // Loads the file. Throws InputError. `historyLimit`: the undo steps' memory at most
    // (edit::SessionOptions).
    SceneEditor(const std::filesystem::path& file, const LoadOptions& options,
                size_t historyLimit = edit::SessionOptions::kDefaultHistoryLimit);
    // A new scene from `text`, to be saved as `file` (which need not exist): modified until
    // saved. Throws InputError.
    SceneEditor(const std::filesystem::path& file, const std::string& text, const LoadOptions& options,
                size_t historyLimit = edit::SessionOptions::kDefaultHistoryLimit);

    // The flattened scene of the document as it is now: a new object after each edit, undo,
    // redo or reload, whose lineage says what changed (the frame source re-packs that alone).
    std::shared_ptr<const Scene> scene() const { return session_.scene(); }
    const std::filesystem::path& file() const { return file_; }
    // The format of the scene's file (a new scene's: its name's), as /state says it: "xml" or
    // "json", the extension a save under another name keeps the format with.
    const char* formatName() const { return session_.document().format == SceneFormat::Json ? "json" : "xml"; }

    // What pixel (x, y) of a settings-sized image from `camera` shows (reference pickPixel):
    // {"node": "object-N", "object": id, "instance", "point", "normal", "distance"} and the
    // object's description (objectJson), or {"object": null} on the background. Throws
    // EditError for a pixel outside the image.
    nlohmann::json pick(const Camera& camera, const RenderSettings& settings, int x, int y);

    // GET /outline: {"nodes": [...]}; GET /node?id=: the node's fields and values.
    nlohmann::json outlineJson();
    nlohmann::json nodeJson(const std::string& id);
    // POST /op: {"changed", "added", "removed"}. `view` is the viewer's camera, for
    // camera-from-view. "revert" undoes the latest step if it is the action's. Throws EditError.
    nlohmann::json operate(const edit::TypedJson& request, const Camera& view);
    // POST /undo, /redo: {"done", "changed", "added", "removed"}.
    nlohmann::json undo();
    nlohmann::json redo();
    bool canUndo() const { return session_.canUndo(); }
    bool canRedo() const { return session_.canRedo(); }

    // The page of today's routes, kept until it speaks /op and /node:
    // an object {"object": id, "node", "type", "path", "line", "material": {...},
    // "transform": [its own transforms], "block_objects": 1, "instances"} (throws EditError
    // for an unknown id); the lights, each {"index", "node", "type", "color", "position", ...};
    // an edit {"object": id, "material": {field: value}} or {"object": id, "transform": [...]}
    // or {"light": index, field: value} (attenuation for the file's function).
    nlohmann::json objectJson(int id);
    nlohmann::json lightsJson();
    void edit(const edit::TypedJson& request);
    void edit(const nlohmann::json& request) { edit(edit::TypedJson{request, {}}); }

    // Writes the document atomically to the file it was opened from, or to `as`, a .xml or
    // .json file (the format its name says: scene_document.h, documentToText) in the opened file's folder (viewer/folder_files.h: no other folder, no link), which
    // must not exist unless `replace`. The opened file is not replaced when another program
    // changed it since the editor read or wrote it (size and bytes, edit/file_stamp.h)
    // unless `overwrite`. Returns where it wrote. Throws BadFileName, FileExists,
    // ChangedOnDisk, EditError or std::runtime_error (the write failed; nothing replaced).
    std::filesystem::path save(const std::optional<std::string>& as = std::nullopt, bool replace = false,
                               bool overwrite = false);
    // The text a save to the file would write now (what a recovery copy keeps: viewer/recovery.h),
    // in the document's own format: a new scene named new.json (an XML document until saved)
    // is kept as XML, which holds whatever the studio added, a torus included, and loads as
    // the same scene whatever the copy's name. Throws InputError.
    std::string documentText() const;
    // The file changed on disk (not by save): loads it again; the history is cleared, as
    // the edits were made to another version; the elements that are the same keep their
    // ids. Throws InputError (the editor is unchanged).
    void reload();
    // The same from a document and its resources read already (without the viewer's lock:
    // scene_watch.cpp), which this only flattens; `stamp`: the file's, taken before it was
    // read. Throws InputError.
    void reload(SceneDocument document, Resources resources, const edit::FileStamp& stamp);
    // The images and meshes the scene uses, by file; the same read again (EditSession::
    // refreshResources), the edits and their history kept. Throws InputError.
    const Resources& resources() const { return session_.resources(); }
    void refreshResources(Resources resources) { session_.refreshResources(std::move(resources)); }
    // The scene's revision: how many edits, undos, redos and reloads have changed it so far.
    uint64_t version() const { return session_.version(); }
    // Throws StaleRevision when `request` (a POST body) carries a "revision" other than the
    // scene's; EditError when it is not a whole number. A request without one is not checked.
    void checkRevision(const nlohmann::json& request) const;
    // The undo and redo steps' memory and its limit: {"bytes", "limit", "steps", "dropped"}.
    nlohmann::json historyJson() const;
    // Whether the document differs from the file as last loaded or saved.
    bool modified() const { return session_.modified(); }

private:
    nlohmann::json stepJson(const std::optional<edit::Outcome>& outcome);

    std::filesystem::path file_;
    LoadOptions options_;
    edit::FileStamp stamp_;  // the file as last read or written
    edit::EditSession session_;
};

}  // namespace ray
