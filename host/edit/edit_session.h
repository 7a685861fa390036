// The editing service: a scene document, its flattened scene, and the operations
// (operations.h) every front end edits it with: the viewer's page (viewer/), the C++ API
// (include/ray/scene.h) and Python, one model for all (docs/modeler-protocol.md).
//
// Each operation is checked whole before anything changes: it is applied to a copy of the
// document, which is flattened, and only then kept; a refused one throws EditError and the
// document, its history and its scene are as they were. Each says what it changed (its
// Outcome), and the new flattened scene carries that change set in its lineage
// (scene/scene_changes.h), so that the renderer re-packs and re-uploads that alone.
//
// History: each user action is one step (an operation, or every operation given the same
// action id in a row: a drag, a colour picked); undo and redo walk the steps. A step keeps
// what its operations changed, as it was (edit/document_patch.h), not a copy of the
// document; the steps' memory is counted (historyBytes) and kept under a limit
// (SessionOptions::historyLimit), the oldest steps dropped first. A session without history
// (the C++ API's) keeps none, and an add at the end of the root tree then changes the
// document and its scene in place, as a scene built in code adds primitives by the thousand.
//
// Revision: every change (an operation, an undo, a redo, a reload) makes a new revision of
// the document; a front end says which one an edit was made against, so that one made
// against an older one (another page edited, the file was reloaded) is refused rather than
// applied to what the user did not see (viewer/scene_editor.h).
//
// Ids across a reload: the document read again keeps the ids of the elements that are the
// same as before (edit/node_matching.h); what is new gets ids never used before, so that a
// stale id names nothing rather than another element.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "edit/document_patch.h"
#include "edit/field_values.h"
#include "edit/node_views.h"
#include "edit/operations.h"
#include "scene/scene.h"
#include "scene/scene_document.h"
#include "scene/scene_loader.h"

namespace ray::edit {

struct SessionOptions {
    LoadOptions load;      // how flattening reads files and reports warnings
    bool history = true;   // keep the steps for undo and redo
    // Where a file an edit names is read from; empty: relative to the document's folder.
    FileResolver resolveFile;
    // The most memory the undo and redo steps hold together; past it the oldest steps go
    // (the latest step is kept whatever its size).
    size_t historyLimit = kDefaultHistoryLimit;

    static constexpr size_t kDefaultHistoryLimit = size_t(64) << 20;  // 64 MiB
};

class EditSession {
public:
    // Takes `document` (with its resources, when it comes with images or meshes made in code)
    // and flattens it. Throws InputError.
    EditSession(SceneDocument document, SessionOptions options, Resources resources = {});

    const SceneDocument& document() const { return document_; }
    const Resources& resources() const { return resources_; }
    // An image or a mesh made in code (the C++ API's handles): added to the resources and
    // the scene, never removed. Returns its index.
    int addImage(Image image);
    int addMesh(TriangleMesh mesh);
    // The document flattened, as it is now: a new object after each change.
    std::shared_ptr<const Scene> scene() const { return scene_; }

    // Applies `operation` as part of user action `action` (empty: an action of its own).
    // Throws EditError; nothing changes then.
    Outcome apply(const Operation& operation, std::string_view action = {});
    // One step back or forward: what it changed; nullopt when there is none.
    std::optional<Outcome> undo();
    std::optional<Outcome> redo();
    // Undoes the latest step if it is `action`'s and forgets it (a cancelled drag): nothing
    // to redo. False when the latest step is another's.
    bool revert(std::string_view action);
    bool canUndo() const { return !undo_.empty(); }
    bool canRedo() const { return !redo_.empty(); }
    size_t undoSteps() const { return undo_.size(); }
    size_t redoSteps() const { return redo_.size(); }
    // About how much memory the undo and redo steps hold, in bytes; and its limit.
    size_t historyBytes() const { return historyBytes_; }
    size_t historyLimit() const { return options_.historyLimit; }
    // Steps dropped so far to keep the history under its limit.
    uint64_t droppedSteps() const { return droppedSteps_; }

    // Whether the document differs from its file as last loaded or saved; saved() says it
    // was just written there.
    bool modified() const { return modified_; }
    void saved();
    void setModified() { modified_ = true; }
    // The document's revision: how many changes (operations, undos, redos, reloads) so far.
    uint64_t version() const { return version_; }

    // The document read again (its file changed on disk): the history goes, as its steps
    // were made to another version; the scene has a lineage of its own (a renderer compares).
    // Elements that are the same keep their ids (edit/node_matching.h).
    void reload(SceneDocument document, Resources resources);
    // Images or meshes read again (their files changed on disk), at the indices they had: the
    // document flattened with them; its history and ids kept. Throws InputError.
    void refreshResources(Resources resources);

    // The outline of the document, and one node's fields (node_views.h; EditError for a
    // node that does not exist).
    std::vector<OutlineEntry> outline() { return edit::outline(document_); }
    NodeView describe(const NodeId& id) { return describeNode(document_, *scene_, id); }

private:
    void refuseWhatJsonCannotHold(const SceneDocument& edited) const;

    struct Step {
        // What gives the document before the step (undo_) or after it (redo_) back, in the
        // order they apply: the step's operations' patches, latest first.
        std::vector<DocumentPatch> patches;
        bool modified = false;
        Outcome outcome;
        std::string action;
        size_t bytes = 0;  // the patches' and the outcome's
    };

    Outcome applyInPlace(const Operation& operation);
    Outcome applyToSettings(const SetFields& set, std::string_view action);
    void pushStep(DocumentPatch patch, const Outcome& outcome, std::string_view action);
    void commit(SceneDocument document, std::shared_ptr<Scene> scene, const Outcome& outcome, std::string_view action);
    // The latest step of `from` applied to the document, moved to `to` as what undoes it.
    Step walkStep(std::vector<Step>& from, std::vector<Step>& to);
    static size_t stepBytes(const Step& step);
    void keepHistoryUnderLimit();
    void forgetHistory();
    std::shared_ptr<Scene> flattenEdited(SceneDocument& document, const SceneChanges& changes);
    FieldContext context();

    SessionOptions options_;
    SceneDocument document_;
    Resources resources_;
    std::shared_ptr<Scene> scene_;
    std::vector<Step> undo_, redo_;
    size_t historyBytes_ = 0;
    uint64_t droppedSteps_ = 0;
    bool modified_ = false;
    uint64_t version_ = 0;
};

}  // namespace ray::edit
