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
// action id in a row: a drag); undo and redo walk the steps, without limit. A session
// without history (the C++ API's) keeps none, and an add at the end of the root tree then
// changes the document and its scene in place, as a scene built in code adds primitives
// by the thousand.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

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

    // Whether the document differs from its file as last loaded or saved; saved() says it
    // was just written there.
    bool modified() const { return modified_; }
    void saved();
    void setModified() { modified_ = true; }
    // How many changes (operations, undos, redos, reloads) so far.
    uint64_t version() const { return version_; }

    // The document read again (its file changed on disk): the history goes, as its steps
    // were made to another version; the scene has a lineage of its own (a renderer compares).
    void reload(SceneDocument document, Resources resources);
    // Images or meshes read again (their files changed on disk), at the indices they had: the
    // document flattened with them; its history and ids kept. Throws InputError.
    void refreshResources(Resources resources);

    // The outline of the document, and one node's fields (node_views.h; EditError for a
    // node that does not exist).
    std::vector<OutlineEntry> outline() { return edit::outline(document_); }
    NodeView describe(const NodeId& id) { return describeNode(document_, *scene_, id); }

private:
    struct Step {
        SceneDocument document;  // before the step (undo_) or after it (redo_)
        bool modified = false;
        Outcome outcome;
        std::string action;
    };

    Outcome applyInPlace(const Operation& operation);
    Outcome applyToSettings(const SetFields& set, std::string_view action);
    void pushStep(const Outcome& outcome, std::string_view action);
    void commit(SceneDocument document, std::shared_ptr<Scene> scene, const Outcome& outcome, std::string_view action);
    std::shared_ptr<Scene> flattenEdited(SceneDocument& document, const SceneChanges& changes);
    FieldContext context();

    SessionOptions options_;
    SceneDocument document_;
    Resources resources_;
    std::shared_ptr<Scene> scene_;
    std::vector<Step> undo_, redo_;
    bool modified_ = false;
    uint64_t version_ = 0;
};

}  // namespace ray::edit
