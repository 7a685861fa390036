#include "edit/operations.h"

#include <algorithm>
#include <set>

#include "core/message_text.h"
#include "edit/edit_error.h"
#include "edit/field_values.h"
#include "edit/node_places.h"
#include "scene/document_edits.h"
#include "scene/parameter_rules.h"
#include "scene/xml_characters.h"

namespace ray::edit {

namespace {

[[noreturn]] void refuse(const std::string& why, const NodeId& node) {
    throw EditError(why, EditError::Kind::Value, "", node.text());
}

SceneChanges geometryChanged() {
    SceneChanges changes;
    changes.geometry = true;
    changes.primitiveMaterials = true;
    changes.materials = true;
    return changes;
}

SceneChanges lightsChanged() {
    SceneChanges changes;
    changes.lights = true;
    return changes;
}

// Checks what the table cannot see in one field: a node's fields together.
void checkNode(const SceneDocument& document, const NodePlace& place) {
    if (place.id.kind == NodeKind::Camera) {
        if (auto broken = brokenCameraAxes(document.camera, "look", "up"))
            throw EditError(broken->sentence(), EditError::Kind::Value, "up", place.id.text());
    } else if (place.id.kind == NodeKind::Light) {
        const Light& light = document.lights[place.index];
        if (light.type != LightType::Directional && light.attenuation == Vec3{0, 0, 0})
            throw EditError("function (0, 0, 0) divides by zero; make c1, c2 or c3 positive", EditError::Kind::Value,
                            "function", place.id.text());
    }
}

// The fields of one node set, the light's type first (it decides which fields apply).
Outcome setFields(SceneDocument& document, const NodeId& id, std::vector<FieldInput> inputs,
                  const FieldContext& context) {
    NodePlace place = requireNode(document, id);
    const std::optional<FieldOwner> owner = fieldOwner(id.kind);
    if (!owner) refuse("a " + std::string(nodeKindName(id.kind)) + " has no fields to set", id);
    if (inputs.empty()) refuse("the edit of " + id.text() + " sets no field", id);
    std::stable_partition(inputs.begin(), inputs.end(),
                          [](const FieldInput& f) { return f.field && f.field->special == SpecialField::LightType; });
    Outcome outcome;
    outcome.changed.push_back(id);
    for (const FieldInput& input : inputs) {
        if (!input.field || input.field->owner != *owner)
            refuse("a " + std::string(nodeKindName(id.kind)) + " has no field '" +
                       (input.field ? std::string(input.field->name) : std::string("?")) + "'",
                   id);
        // A light's field its type does not use (a point light's direction) is set all the
        // same: a light keeps it, as a file may, for when its type changes.
        const bool splits = id.kind == NodeKind::Object && place.block().items.size() > 1 &&
                            (input.field->special == SpecialField::Transforms || input.field->special == SpecialField::World);
        outcome.outline = outcome.outline || splits || input.field->special == SpecialField::TreeName;
        outcome.changes |= setField(document, place, input, context);
        // Found again only when the edit moved it (a transblock of its own) or re-keyed its
        // tree (a rename): a lookup walks the document, and an add of one object to 10^4
        // sets a dozen fields.
        if (splits || input.field->special == SpecialField::TreeName) place = requireNode(document, id);
    }
    checkNode(document, place);
    return outcome;
}

// A new primitive node of `shape`, its mesh resolved.
PrimitiveNode newPrimitive(SceneDocument& document, const AddPrimitive& add, const FieldContext& context) {
    if (add.shape == PrimitiveType::Csg)
        throw EditError("a csg object is not added this way; add its operands' shapes", EditError::Kind::Value, "shape");
    PrimitiveNode node;
    node.type = add.shape;
    node.id = document.nextObjectId++;
    ++document.primitiveElements;
    if (add.shape != PrimitiveType::Mesh) return node;
    if (add.mesh >= 0) {
        if (size_t(add.mesh) >= context.resources.meshes.size())
            throw EditError("mesh " + std::to_string(add.mesh) + " does not exist; use a handle returned by add_mesh",
                            EditError::Kind::Value, "mesh");
        node.mesh = add.mesh;
        return node;
    }
    if (add.meshFile.empty()) throw EditError("a mesh needs its file, an .obj in the scene's folder", EditError::Kind::Value, "file");
    checkWritable("file", add.meshFile, "");
    std::filesystem::path file;
    try {
        file = context.resolveFile(add.meshFile, FileUse::Mesh);
    } catch (const EditError&) {
        throw;
    } catch (const std::exception& e) {
        throw EditError(e.what(), EditError::Kind::Value, "file");  // the resolver names the file (FileResolver)
    }
    loadMeshInto(context.resources, file, "file");
    node.filesToSet().meshFile = file;
    return node;
}

Outcome addPrimitive(SceneDocument& document, const AddPrimitive& add, const FieldContext& context) {
    Outcome outcome;
    outcome.changes = geometryChanged();
    outcome.outline = true;
    Block block;
    block.id = document.nextBlockId++;
    composeBlock(block);
    block.items.push_back(newPrimitive(document, add, context));
    const NodeId object{NodeKind::Object, std::get<PrimitiveNode>(block.items[0]).id};
    outcome.added = {object, {NodeKind::Block, block.id}};
    if (add.parent) {
        if (add.parent->kind != NodeKind::Block)
            refuse("a primitive is added inside a transblock, not a " + std::string(nodeKindName(add.parent->kind)),
                   *add.parent);
        NodePlace parent = requireNode(document, *add.parent);
        TreeNode tree;
        tree.blocks.push_back(std::move(block));
        parent.block().items.push_back(Box<TreeNode>(std::move(tree)));
    } else {
        document.rootToSet().tree.blocks.push_back(std::move(block));
    }
    if (!add.fields.empty()) {
        Outcome fields = setFields(document, object, add.fields, context);
        outcome.changes |= fields.changes;
    }
    return outcome;
}

Outcome addLight(SceneDocument& document, const AddLight& add, const FieldContext& context) {
    Light light;
    light.type = add.type;
    const size_t index = ray::addLight(document, light);
    const NodeId id{NodeKind::Light, document.lightIds[index]};
    Outcome outcome;
    outcome.changes = lightsChanged();
    outcome.outline = true;
    outcome.added = {id};
    if (!add.fields.empty()) setFields(document, id, add.fields, context);
    return outcome;
}

// How many placements name the tree `name`.
size_t placementsOf(SceneDocument& document, const std::string& name) {
    size_t count = 0;
    walkNodes(document, [&](const NodePlace& place) {
        if (place.id.kind == NodeKind::Placement && place.placement().name == name) ++count;
        return false;
    });
    return count;
}

void removeNode(SceneDocument& document, const NodePlace& place) {
    switch (place.id.kind) {
        case NodeKind::Light: ray::removeLight(document, place.index); return;
        case NodeKind::Block: place.holder->blocks.erase(place.holder->blocks.begin() + std::ptrdiff_t(place.index)); return;
        case NodeKind::Object:
        case NodeKind::Placement:
        case NodeKind::Csg: place.block().items.erase(place.block().items.begin() + std::ptrdiff_t(place.index)); return;
        case NodeKind::Tree: {
            const std::string name = place.tree->name;
            document.trees.erase(name);
            std::erase(document.treeOrder, name);
            return;
        }
        case NodeKind::Camera:
        case NodeKind::Globals: break;
    }
}

Outcome deleteNodes(SceneDocument& document, const DeleteNodes& remove) {
    if (remove.nodes.empty()) throw EditError("delete: name the nodes to delete");
    Outcome outcome;
    outcome.outline = true;
    for (const NodeId& id : remove.nodes) {  // all checked before any goes
        const NodePlace place = requireNode(document, id);
        if (id.kind == NodeKind::Camera || id.kind == NodeKind::Globals)
            refuse("the " + id.text() + " cannot be deleted; set its fields instead", id);
        if (id.kind == NodeKind::Tree) {
            if (place.tree->name == "root") refuse("the tree named root is the scene; delete what it holds instead", id);
            if (size_t n = placementsOf(document, place.tree->name))
                refuse("master '" + quotedForMessage(place.tree->name, 60) + "' is placed " + std::to_string(n) +
                           " times; delete its placements first",
                       id);
        }
    }
    for (const NodeId& id : remove.nodes) {
        const std::optional<NodePlace> place = findNode(document, id);
        if (!place) continue;  // went with a transblock deleted before it
        outcome.changes |= id.kind == NodeKind::Light ? lightsChanged() : geometryChanged();
        removeNode(document, *place);
        outcome.removed.push_back(id);
    }
    return outcome;
}

// Fresh ids for a copy of a subtree, and no element of the file's text: it is written afresh.
class FreshCopy {
public:
    explicit FreshCopy(SceneDocument& document) : document_(document) {}

    void tree(TreeNode& node) {
        node.source = kNoSource;
        for (Block& b : node.blocks) block(b);
    }
    void block(Block& b) {
        b.id = document_.nextBlockId++;
        b.source = kNoSource;
        for (SceneItem& i : b.items) item(i);
    }
    void item(SceneItem& item) {
        if (auto* primitive = std::get_if<PrimitiveNode>(&item)) {
            primitive->id = document_.nextObjectId++;
            primitive->source = kNoSource;
            primitive->line = 0;
            ++document_.primitiveElements;
        } else if (auto* master = std::get_if<MasterReference>(&item)) {
            master->id = document_.nextNodeId++;
            master->source = kNoSource;
            master->line = 0;
        } else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
            tree(**subtree);
        } else if (auto* csg = std::get_if<Box<CsgNode>>(&item)) {
            (*csg)->id = document_.nextNodeId++;
            (*csg)->source = kNoSource;
            (*csg)->line = 0;
            for (TreeNode& operand : (*csg)->operands) tree(operand);
        }
    }

private:
    SceneDocument& document_;
};

NodeId itemId(const SceneItem& item) {
    if (const auto* primitive = std::get_if<PrimitiveNode>(&item)) return {NodeKind::Object, primitive->id};
    if (const auto* master = std::get_if<MasterReference>(&item)) return {NodeKind::Placement, master->id};
    return {NodeKind::Csg, std::get<Box<CsgNode>>(item)->id};
}

NodeId duplicate(SceneDocument& document, const NodePlace& place) {
    FreshCopy fresh(document);
    switch (place.id.kind) {
        case NodeKind::Light: {
            const size_t index = ray::addLight(document, document.lights[place.index]);
            return {NodeKind::Light, document.lightIds[index]};
        }
        case NodeKind::Block: {
            Block copy = place.block();
            fresh.block(copy);
            const NodeId id{NodeKind::Block, copy.id};
            place.holder->blocks.insert(place.holder->blocks.begin() + std::ptrdiff_t(place.index + 1), std::move(copy));
            return id;
        }
        case NodeKind::Object:
        case NodeKind::Placement:
        case NodeKind::Csg: {
            SceneItem copy = place.item();
            fresh.item(copy);
            const NodeId id = itemId(copy);
            place.block().items.insert(place.block().items.begin() + std::ptrdiff_t(place.index + 1), std::move(copy));
            return id;
        }
        case NodeKind::Tree:
        case NodeKind::Camera:
        case NodeKind::Globals: break;
    }
    refuse("a " + std::string(nodeKindName(place.id.kind)) + " cannot be duplicated", place.id);
}

Outcome duplicateNodes(SceneDocument& document, const DuplicateNodes& copies) {
    if (copies.nodes.empty()) throw EditError("duplicate: name the nodes to copy");
    Outcome outcome;
    outcome.outline = true;
    for (const NodeId& id : copies.nodes) requireNode(document, id);
    for (const NodeId& id : copies.nodes) {
        const NodePlace place = requireNode(document, id);
        outcome.added.push_back(duplicate(document, place));
        outcome.changes |= id.kind == NodeKind::Light ? lightsChanged() : geometryChanged();
    }
    return outcome;
}

Outcome groupNodes(SceneDocument& document, const GroupNodes& group) {
    std::vector<int> ids;
    for (const NodeId& id : group.nodes) {
        if (id.kind != NodeKind::Object) refuse("group: only objects are grouped, not a " + std::string(nodeKindName(id.kind)), id);
        requireNode(document, id);
        ids.push_back(id.number);
    }
    int block = -1;
    try {
        block = groupIntoTransblock(document, ids);
    } catch (const InputError& e) {
        const std::string why = e.what();
        throw EditError(why.starts_with("error: ") ? why.substr(7) : why);
    }
    Outcome outcome;
    outcome.changes = geometryChanged();
    outcome.outline = true;
    outcome.added = {{NodeKind::Block, block}};
    return outcome;
}

// The first name `base`_2, `base`_3, ... that no tree has, of at most kMaxTreeName
// characters: a long base is cut to fit, between two characters.
std::string freeName(const SceneDocument& document, const std::string& base) {
    for (int n = 2;; ++n) {
        const std::string suffix = "_" + std::to_string(n);
        const std::string name = std::string(firstCharacters(base, kMaxTreeName - suffix.size())) + suffix;
        if (!document.trees.count(name)) return name;
    }
}

Outcome makeUnique(SceneDocument& document, const MakeUnique& unique) {
    if (unique.placement.kind != NodeKind::Placement)
        refuse("make-unique takes a placement of a master, not a " + std::string(nodeKindName(unique.placement.kind)),
               unique.placement);
    const NodePlace place = requireNode(document, unique.placement);
    const std::string master = place.placement().name;
    auto original = document.trees.find(master);
    if (original == document.trees.end())
        refuse("placement " + unique.placement.text() + " names master '" + quotedForMessage(master, 60) +
                   "', which no tree is",
               unique.placement);
    if (placementsOf(document, master) < 2)
        refuse(unique.placement.text() + " is the only placement of master '" + quotedForMessage(master, 60) +
                   "': it is unique already",
               unique.placement);
    NamedTree copy = original->second;
    copy.name = freeName(document, master);
    copy.id = document.nextNodeId++;
    copy.line = 0;
    copy.state = NamedTree::State::Uncounted;
    FreshCopy(document).tree(copy.tree);
    const std::string name = copy.name;
    const NodeId tree{NodeKind::Tree, copy.id};
    document.trees.emplace(name, std::move(copy));
    document.treeOrder.push_back(name);
    place.placement().name = name;
    document.resolveMasters();
    Outcome outcome;
    outcome.changes.materials = true;  // the copy's objects have materials of their own
    outcome.changes.primitiveMaterials = true;
    outcome.outline = true;
    outcome.changed = {unique.placement};
    outcome.added = {tree};
    return outcome;
}

}  // namespace

const char* operationName(const Operation& operation) {
    static const char* const kNames[] = {"set", "add-primitive", "add-light", "delete", "duplicate", "group",
                                         "make-unique"};
    return kNames[operation.index()];
}

Outcome& Outcome::operator+=(const Outcome& later) {
    changes |= later.changes;
    auto append = [](std::vector<NodeId>& to, const std::vector<NodeId>& from) {
        for (const NodeId& id : from)
            if (std::find(to.begin(), to.end(), id) == to.end()) to.push_back(id);
    };
    append(changed, later.changed);
    append(added, later.added);
    append(removed, later.removed);
    outline = outline || later.outline;
    return *this;
}

Outcome perform(SceneDocument& document, const Operation& operation, const FieldContext& context) {
    return std::visit(
        [&](const auto& op) -> Outcome {
            using Op = std::decay_t<decltype(op)>;
            if constexpr (std::is_same_v<Op, SetFields>) return setFields(document, op.node, op.fields, context);
            else if constexpr (std::is_same_v<Op, AddPrimitive>) return addPrimitive(document, op, context);
            else if constexpr (std::is_same_v<Op, AddLight>) return addLight(document, op, context);
            else if constexpr (std::is_same_v<Op, DeleteNodes>) return deleteNodes(document, op);
            else if constexpr (std::is_same_v<Op, DuplicateNodes>) return duplicateNodes(document, op);
            else if constexpr (std::is_same_v<Op, GroupNodes>) return groupNodes(document, op);
            else return makeUnique(document, op);
        },
        operation);
}

bool appliesInPlace(const SceneDocument& document, const Operation& operation, const Resources& resources) {
    const auto* add = std::get_if<AddPrimitive>(&operation);
    if (!add || add->parent || add->shape == PrimitiveType::Csg) return false;
    if (add->shape == PrimitiveType::Mesh && (add->mesh < 0 || size_t(add->mesh) >= resources.meshes.size()))
        return false;
    if (!document.trees.count("root") && !document.trees.empty()) return false;
    for (const FieldInput& input : add->fields) {
        if (!input.field || input.field->owner != FieldOwner::Object) return false;
        const SpecialField special = input.field->special;
        const bool member = special == SpecialField::None;
        const auto* image = std::get_if<ImageHandle>(&input.value);
        const auto* file = std::get_if<std::string>(&input.value);
        const bool handle = (special == SpecialField::Texture || special == SpecialField::BumpMap) &&
                            ((image && image->index >= 0 && size_t(image->index) < resources.images.size()) ||
                             (file && file->empty()));  // a handle, or none
        const bool repeat = special == SpecialField::TextureU || special == SpecialField::TextureV ||
                            special == SpecialField::BumpMapU || special == SpecialField::BumpMapV;
        if (!member && !handle && !repeat && special != SpecialField::Transforms) return false;
        try {
            checkFieldValue(input, "");
        } catch (const EditError&) {
            return false;  // refused the usual way, on a copy, with its message
        }
    }
    return true;
}

}  // namespace ray::edit
