// What `ray view` edits: the scene document of the file it opened (scene/scene_document.h),
// its flattened scene for the frames, edits given as JSON by the page, undo and redo, and
// saving. Kept apart from the HTTP server so that tests drive it directly.
//
// Every edit is checked whole before anything changes: a bad one (an unknown object, a
// negative color, a transform that flattens to nothing) throws EditError with a message
// and leaves the document, its history and the scene as they were. A good one is applied
// to a copy of the document, which is flattened; only then does it replace the document,
// the one before going to the undo history. Edits of the same thing in quick succession
// (a color dragged across the picker) are one step of the history.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/render_settings.h"
#include "scene/scene.h"
#include "scene/scene_document.h"
#include "scene/scene_loader.h"

namespace ray {

struct EditError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// What POST /save asks: {"as": name} (absent: the file the editor opened) and
// {"replace": true} to replace an existing file.
struct SaveRequest {
    std::optional<std::string> as;
    bool replace = false;
};
// Throws EditError when a field has the wrong type.
SaveRequest saveRequestFrom(const nlohmann::json& request);

class SceneEditor {
public:
    // Loads the file. Throws InputError.
    SceneEditor(const std::filesystem::path& file, const LoadOptions& options);
    // A new scene from `text`, to be saved as `file` (which need not exist): modified until
    // saved. Throws InputError.
    SceneEditor(const std::filesystem::path& file, const std::string& text, const LoadOptions& options);

    // The flattened scene of the document as it is now: a new object after each edit, undo,
    // redo or reload (the frame source then prepares only what changed).
    std::shared_ptr<const Scene> scene() const { return scene_; }
    const std::filesystem::path& file() const { return file_; }

    // What pixel (x, y) of a settings-sized image from `camera` shows (reference pickPixel):
    // {"object": id, "instance", "point", "normal", "distance"} and the object's description
    // (objectJson), or {"object": null} on the background. Throws EditError for a pixel
    // outside the image.
    nlohmann::json pick(const Camera& camera, const RenderSettings& settings, int x, int y) const;
    // An object: {"object": id, "type", "path", "line", "material": {...}, "transform": [ops],
    // "block_objects": how many objects share its transblock (they move with it),
    // "instances": how many times it is placed}. Throws EditError for an unknown id.
    nlohmann::json objectJson(int id) const;
    // The lights, each {"index", "type", "color", "position", "direction", "attenuation",
    // "angle", "penumbra", "width", "height"}.
    nlohmann::json lightsJson() const;

    // One edit (see the page): {"object": id, "material": {field: value, ...}},
    // {"object": id, "transform": [{"kind": "translate"|"rotate"|"scale", "v": [...]}, ...]},
    // or {"light": index, field: value, ...}. Throws EditError.
    void edit(const nlohmann::json& request);
    bool canUndo() const { return !undo_.empty(); }
    bool canRedo() const { return !redo_.empty(); }
    // False when there is nothing to undo (redo).
    bool undo();
    bool redo();
    // Writes the document atomically to the file it was opened from, or to `as`, a .xml file
    // in the opened file's folder (viewer/folder_files.h: no other folder, no link), which
    // must not exist unless `replace`. Returns where it wrote. Throws BadFileName,
    // FileExists, EditError or std::runtime_error (the write failed; nothing replaced).
    std::filesystem::path save(const std::optional<std::string>& as = std::nullopt, bool replace = false);
    // The file changed on disk (not by save): loads it again; the history is cleared, as
    // the edits were made to another version. Throws InputError (the editor is unchanged).
    void reload();
    // How many edits, undos, redos and reloads have changed the scene so far.
    uint64_t version() const { return version_; }
    // Whether the document differs from the file as last loaded or saved.
    bool modified() const { return modified_; }

private:
    struct State {
        SceneDocument document;
        bool modified = false;
    };
    void apply(SceneDocument document, const std::string& key);
    std::shared_ptr<const Scene> flatten(SceneDocument& document);

    std::filesystem::path file_;
    LoadOptions options_;
    mutable SceneDocument document_;  // mutable: findObject walks it by non-const reference
    Resources resources_;
    std::shared_ptr<const Scene> scene_;
    std::vector<State> undo_, redo_;
    std::string lastKey_;  // what the last edit changed, for merging quick successive edits
    std::chrono::steady_clock::time_point lastEditAt_;
    uint64_t version_ = 0;
    bool modified_ = false;
};

}  // namespace ray
