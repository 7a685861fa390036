#include "edit/edit_session.h"

#include <algorithm>

#include "core/message_text.h"
#include "edit/edit_error.h"
#include "edit/node_matching.h"
#include "scene/json_splices.h"

namespace ray::edit {

namespace {

// The default: a relative name is found from the document's folder.
FileResolver besideDocument(const SceneDocument& document) {
    const std::filesystem::path folder = document.file.parent_path();
    return [folder](const std::string& name, FileUse) {
        const std::filesystem::path file(name);
        return file.is_absolute() ? file : folder / file;
    };
}

// The instance flattening makes of an object alone in a transblock at the end of the root
// tree (scene_loader_flatten.cpp's makeInstance): appended, its material last.
void appendInstance(Scene& scene, const Block& block, const PrimitiveNode& node, const Resources& resources) {
    PrimitiveInstance instance;
    instance.objectToWorld = Affine::identity() * block.toParent;
    instance.worldToObject = block.fromParent * Affine::identity();
    instance.type = node.type;
    instance.material = int(scene.materials.size());
    instance.mesh = node.type == PrimitiveType::Mesh ? node.mesh : -1;
    instance.sourceObject = node.id;
    fitObjectBox(instance, resources.meshes);
    scene.materials.push_back(node.material);
    scene.primitives.push_back(instance);
}

// A set of the camera's, the globals' or a light's fields: what the flattened scene holds
// as copies of the document's own (no primitive changes), so no flattening is needed.
bool setsSettingsOnly(const Operation& operation) {
    const auto* set = std::get_if<SetFields>(&operation);
    if (!set) return false;
    const NodeKind kind = set->node.kind;
    return kind == NodeKind::Camera || kind == NodeKind::Globals || kind == NodeKind::Light;
}

}  // namespace

EditSession::EditSession(SceneDocument document, SessionOptions options, Resources resources)
    : options_(std::move(options)), document_(std::move(document)), resources_(std::move(resources)) {
    assignNodeIds(document_);
    if (!options_.resolveFile) options_.resolveFile = besideDocument(document_);
    scene_ = std::make_shared<Scene>(flattenDocument(document_, resources_, options_.load));
}

// A document read from JSON is saved as JSON (scene/json_splices.h): an edit the format
// cannot hold is refused now, not at the save.
void EditSession::refuseWhatJsonCannotHold(const SceneDocument& edited) const {
    if (std::optional<std::string> why = jsonUnsaveable(edited, resources_))
        throw EditError("the edit was not made: the scene is a JSON scene, and " + *why);
}

FieldContext EditSession::context() { return FieldContext{resources_, *scene_, options_.resolveFile}; }

std::shared_ptr<Scene> EditSession::flattenEdited(SceneDocument& document, const SceneChanges& changes) {
    std::shared_ptr<Scene> scene;
    try {
        scene = std::make_shared<Scene>(flattenDocument(document, resources_, options_.load));
    } catch (const InputError& e) {
        const std::string why = e.what();
        throw EditError("the edit was not made: " + quotedForMessage(why.starts_with("error: ") ? why.substr(7) : why, 400));
    }
    scene->lineage = SceneLineage::after(scene_->lineage, changes);
    return scene;
}

Outcome EditSession::apply(const Operation& operation, std::string_view action) {
    if (setsSettingsOnly(operation)) return applyToSettings(std::get<SetFields>(operation), action);
    if (!options_.history && !document_.jsonSource && appliesInPlace(document_, operation, resources_))
        return applyInPlace(operation);
    SceneDocument edited = document_;
    const Outcome outcome = perform(edited, operation, context());
    placeLightsByTheirGroups(document_, edited);
    refuseWhatJsonCannotHold(edited);
    std::shared_ptr<Scene> scene = flattenEdited(edited, outcome.changes);
    commit(std::move(edited), std::move(scene), outcome, action);
    return outcome;
}

// An add checked whole before it changes anything (appliesInPlace): the document and its
// scene changed as a copy's flattening would change them.
Outcome EditSession::applyInPlace(const Operation& operation) {
    const Outcome outcome = perform(document_, operation, context());
    if (scene_.use_count() > 1) scene_ = std::make_shared<Scene>(*scene_);  // a renderer holds the old one
    const NamedTree& root = document_.trees.at("root");
    const Block& block = root.tree.blocks.back();
    appendInstance(*scene_, block, std::get<PrimitiveNode>(block.items.front()), resources_);
    scene_->lineage = SceneLineage::after(scene_->lineage, outcome.changes);
    modified_ = true;
    ++version_;
    return outcome;
}

// The camera, the globals or a light: set on a document of those alone (checked whole
// there), then copied into the document and its scene, which needs no flattening.
Outcome EditSession::applyToSettings(const SetFields& set, std::string_view action) {
    SceneDocument settings;
    settings.file = document_.file;
    settings.camera = document_.camera;
    settings.globals = document_.globals;
    settings.lights = document_.lights;
    settings.lightIds = document_.lightIds;
    settings.typedNumbers = document_.typedNumbers;
    const Outcome outcome = perform(settings, set, context());
    if (document_.jsonSource) {
        SceneDocument edited = document_;
        edited.camera = settings.camera;
        edited.globals = settings.globals;
        edited.lights = settings.lights;
        edited.typedNumbers = settings.typedNumbers;
        refuseWhatJsonCannotHold(edited);
    }
    if (options_.history) pushStep(patchBetween(document_, settings, true), outcome, action);
    document_.camera = settings.camera;
    document_.globals = settings.globals;
    document_.lights = std::move(settings.lights);
    document_.typedNumbers = std::move(settings.typedNumbers);
    if (scene_.use_count() > 1) scene_ = std::make_shared<Scene>(*scene_);  // a renderer holds the old one
    scene_->camera = document_.camera;
    scene_->globals = document_.globals;
    scene_->lights = document_.lights;
    scene_->lineage = SceneLineage::after(scene_->lineage, outcome.changes);
    modified_ = true;
    ++version_;
    return outcome;
}

// `patch` (what gives the document before the operation back) becomes the latest step, or
// part of it when the latest is `action`'s: a drag, a colour being picked.
void EditSession::pushStep(DocumentPatch patch, const Outcome& outcome, std::string_view action) {
    const bool sameAction = !action.empty() && !undo_.empty() && undo_.back().action == action && redo_.empty();
    historyBytes_ -= std::min(historyBytes_, [&] {
        size_t redone = 0;
        for (const Step& step : redo_) redone += step.bytes;
        return redone;
    }());
    redo_.clear();
    if (sameAction) {
        Step& step = undo_.back();
        historyBytes_ -= step.bytes;
        step.outcome += outcome;
        step.patches.insert(step.patches.begin(), std::move(patch));
        step.bytes = stepBytes(step);
        historyBytes_ += step.bytes;
    } else {
        Step step{{}, modified_, outcome, std::string(action), 0};
        step.patches.push_back(std::move(patch));
        step.bytes = stepBytes(step);
        historyBytes_ += step.bytes;
        undo_.push_back(std::move(step));
    }
    keepHistoryUnderLimit();
}

size_t EditSession::stepBytes(const Step& step) {
    size_t bytes = sizeof(Step) + step.action.capacity() + step.patches.capacity() * sizeof(DocumentPatch) +
                   (step.outcome.changed.capacity() + step.outcome.added.capacity() + step.outcome.removed.capacity()) *
                       sizeof(NodeId);
    for (const DocumentPatch& patch : step.patches) bytes += patch.bytes() - sizeof(DocumentPatch);
    return bytes;
}

// The oldest steps go first; the latest stays, so that what was just done can be undone.
void EditSession::keepHistoryUnderLimit() {
    size_t drop = 0;
    while (historyBytes_ > options_.historyLimit && drop + 1 < undo_.size()) historyBytes_ -= undo_[drop++].bytes;
    undo_.erase(undo_.begin(), undo_.begin() + std::ptrdiff_t(drop));
    droppedSteps_ += drop;
}

void EditSession::forgetHistory() {
    undo_.clear();
    redo_.clear();
    historyBytes_ = 0;
}

int EditSession::addImage(Image image) {
    resources_.images.push_back(image);
    resources_.imageFiles.push_back("<memory>");
    if (scene_.use_count() > 1) scene_ = std::make_shared<Scene>(*scene_);
    scene_->images.push_back(std::move(image));
    scene_->imageFiles.push_back("<memory>");
    SceneChanges changes;
    changes.images = true;
    scene_->lineage = SceneLineage::after(scene_->lineage, changes);
    ++version_;
    return int(resources_.images.size()) - 1;
}

int EditSession::addMesh(TriangleMesh mesh) {
    resources_.meshes.push_back(mesh);
    resources_.meshFiles.push_back("<memory>");
    if (scene_.use_count() > 1) scene_ = std::make_shared<Scene>(*scene_);
    scene_->meshes.push_back(std::move(mesh));
    scene_->meshFiles.push_back("<memory>");
    SceneChanges changes;
    changes.geometry = true;  // the meshes' tables are the BVH's
    scene_->lineage = SceneLineage::after(scene_->lineage, changes);
    ++version_;
    return int(resources_.meshes.size()) - 1;
}

void EditSession::commit(SceneDocument document, std::shared_ptr<Scene> scene, const Outcome& outcome,
                         std::string_view action) {
    if (options_.history) pushStep(patchBetween(document_, document), outcome, action);
    document_ = std::move(document);
    scene_ = std::move(scene);
    modified_ = true;
    ++version_;
}

// The step's patches applied to a copy of the document (a flattening that fails leaves the
// session as it was), their inverses the step that goes back.
EditSession::Step EditSession::walkStep(std::vector<Step>& from, std::vector<Step>& to) {
    Step& step = from.back();
    SceneDocument document = document_;
    Step back{{}, modified_, step.outcome, step.action, 0};
    for (const DocumentPatch& patch : step.patches) back.patches.insert(back.patches.begin(), applyPatch(document, patch));
    std::shared_ptr<Scene> scene = flattenEdited(document, step.outcome.changes);
    Step walked = std::move(step);
    from.pop_back();
    historyBytes_ -= walked.bytes;
    back.bytes = stepBytes(back);
    historyBytes_ += back.bytes;
    to.push_back(std::move(back));
    document_ = std::move(document);
    scene_ = std::move(scene);
    modified_ = walked.modified;
    ++version_;
    keepHistoryUnderLimit();
    return walked;
}

std::optional<Outcome> EditSession::undo() {
    if (undo_.empty()) return std::nullopt;
    Outcome undone = walkStep(undo_, redo_).outcome;
    // The page reads the added nodes as removed and the removed as added.
    std::swap(undone.added, undone.removed);
    return undone;
}

std::optional<Outcome> EditSession::redo() {
    if (redo_.empty()) return std::nullopt;
    return walkStep(redo_, undo_).outcome;
}

bool EditSession::revert(std::string_view action) {
    if (action.empty() || undo_.empty() || undo_.back().action != action || !redo_.empty()) return false;
    undo();
    historyBytes_ -= redo_.back().bytes;
    redo_.pop_back();
    return true;
}

void EditSession::saved() {
    modified_ = false;
    for (Step& step : undo_) step.modified = true;  // each differs from the file now written
    for (Step& step : redo_) step.modified = true;
    if (!undo_.empty()) undo_.back().action.clear();  // the next edit is a step of its own
}

void EditSession::reload(SceneDocument document, Resources resources) {
    assignNodeIds(document);
    keepIdsAcrossReload(document_, document);
    auto scene = std::make_shared<Scene>(flattenDocument(document, resources, options_.load));
    document_ = std::move(document);
    resources_ = std::move(resources);
    scene_ = std::move(scene);
    forgetHistory();
    modified_ = false;
    ++version_;
}

void EditSession::refreshResources(Resources resources) {
    auto scene = std::make_shared<Scene>(flattenDocument(document_, resources, options_.load));
    resources_ = std::move(resources);
    scene_ = std::move(scene);
    ++version_;
}

}  // namespace ray::edit
