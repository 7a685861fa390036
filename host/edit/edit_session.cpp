#include "edit/edit_session.h"

#include "core/message_text.h"
#include "edit/edit_error.h"

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
    if (!options_.history && appliesInPlace(document_, operation, resources_)) return applyInPlace(operation);
    SceneDocument edited = document_;
    const Outcome outcome = perform(edited, operation, context());
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
    pushStep(outcome, action);
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

// The document as it is becomes the step before `outcome` (or the step of `action` takes
// it in, when it is the latest's).
void EditSession::pushStep(const Outcome& outcome, std::string_view action) {
    if (!options_.history) return;
    const bool sameAction = !action.empty() && !undo_.empty() && undo_.back().action == action && redo_.empty();
    if (sameAction) undo_.back().outcome += outcome;
    else undo_.push_back({document_, modified_, outcome, std::string(action)});
    redo_.clear();
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
    if (options_.history) {
        const bool sameAction = !action.empty() && !undo_.empty() && undo_.back().action == action && redo_.empty();
        if (sameAction) undo_.back().outcome += outcome;
        else undo_.push_back({std::move(document_), modified_, outcome, std::string(action)});
        redo_.clear();
    }
    document_ = std::move(document);
    scene_ = std::move(scene);
    modified_ = true;
    ++version_;
}

std::optional<Outcome> EditSession::undo() {
    if (undo_.empty()) return std::nullopt;
    Step step = std::move(undo_.back());
    undo_.pop_back();
    std::shared_ptr<Scene> scene = flattenEdited(step.document, step.outcome.changes);
    redo_.push_back({std::move(document_), modified_, step.outcome, step.action});
    document_ = std::move(step.document);
    scene_ = std::move(scene);
    modified_ = step.modified;
    ++version_;
    // The page reads the added nodes as removed and the removed as added.
    Outcome undone = step.outcome;
    std::swap(undone.added, undone.removed);
    return undone;
}

std::optional<Outcome> EditSession::redo() {
    if (redo_.empty()) return std::nullopt;
    Step step = std::move(redo_.back());
    redo_.pop_back();
    std::shared_ptr<Scene> scene = flattenEdited(step.document, step.outcome.changes);
    undo_.push_back({std::move(document_), modified_, step.outcome, step.action});
    document_ = std::move(step.document);
    scene_ = std::move(scene);
    modified_ = step.modified;
    ++version_;
    return step.outcome;
}

bool EditSession::revert(std::string_view action) {
    if (action.empty() || undo_.empty() || undo_.back().action != action || !redo_.empty()) return false;
    undo();
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
    auto scene = std::make_shared<Scene>(flattenDocument(document, resources, options_.load));
    document_ = std::move(document);
    resources_ = std::move(resources);
    scene_ = std::move(scene);
    undo_.clear();
    redo_.clear();
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
