#include "edit/field_values.h"

#include <cmath>
#include <limits>

#include "core/message_text.h"
#include "edit/edit_error.h"
#include "image/image.h"
#include "scene/document_edits.h"
#include "scene/mesh.h"
#include "scene/xml_characters.h"

namespace ray::edit {

namespace fs = std::filesystem;

namespace {

// At most this many transforms in one transblock set by an edit (a file may hold more).
constexpr size_t kMaxTransforms = 16;

[[noreturn]] void refuse(const std::string& why, const EditField& field, const std::string& node,
                         EditError::Kind kind = EditError::Kind::Value) {
    throw EditError(why, kind, std::string(field.name), node);
}

// What a value of `kind` is, for "takes ..." messages.
std::string kindPhrase(FieldKind kind) {
    switch (kind) {
        case FieldKind::Number: return "a number";
        case FieldKind::Color: return "a color, three numbers [r, g, b]";
        case FieldKind::Vector: return "three numbers [x, y, z]";
        case FieldKind::Choice: return "one of its choices, a string";
        case FieldKind::Text: return "a string";
        case FieldKind::File: return "a file name, a string";
        case FieldKind::Transforms: return "a list of transforms";
        case FieldKind::Matrix: return "a matrix, twelve numbers (three rows)";
    }
    return "a value";
}

bool holdsKind(const FieldValue& value, FieldKind kind) {
    switch (kind) {
        case FieldKind::Number: return std::holds_alternative<double>(value);
        case FieldKind::Color:
        case FieldKind::Vector: return std::holds_alternative<Vec3>(value);
        case FieldKind::Choice:
        case FieldKind::Text: return std::holds_alternative<std::string>(value);
        case FieldKind::File: return std::holds_alternative<std::string>(value) || std::holds_alternative<ImageHandle>(value);
        case FieldKind::Transforms: return std::holds_alternative<std::vector<TransformOp>>(value);
        case FieldKind::Matrix: return std::holds_alternative<Affine>(value);
    }
    return false;
}

void checkRule(const EditField& field, const std::optional<RuleBroken>& broken, const std::string& node) {
    if (broken) refuse(broken->sentence(), field, node);
}

size_t numbersOf(TransformKind kind) {
    return kind == TransformKind::Matrix ? 12 : kind == TransformKind::Rotate ? 4 : 3;
}

const char* transformName(TransformKind kind) {
    switch (kind) {
        case TransformKind::Translate: return "translate";
        case TransformKind::Rotate: return "rotate";
        case TransformKind::Scale: return "scale";
        case TransformKind::Matrix: return "matrix";
    }
    return "?";
}

void checkTransforms(const EditField& field, const std::vector<TransformOp>& ops, const std::string& node) {
    if (ops.size() > kMaxTransforms)
        refuse(std::string(field.name) + " holds " + std::to_string(ops.size()) + " transforms; an edit sets at most " +
                   std::to_string(kMaxTransforms) + " (combine them into a matrix)",
               field, node);
    for (size_t i = 0; i < ops.size(); ++i) {
        const TransformOp& op = ops[i];
        for (size_t k = 0; k < numbersOf(op.kind); ++k)
            if (!std::isfinite(op.v[k]))
                refuse(std::string(field.name) + " " + std::to_string(i + 1) + " (" + transformName(op.kind) +
                           ") holds a number that is not finite; a scenefile holds finite decimal numbers only",
                       field, node);
        if (auto why = op.whySingular())
            refuse(std::string(field.name) + " " + std::to_string(i + 1) + " (" + transformName(op.kind) + "): " +
                       *why + "; it must be invertible",
                   field, node);
    }
}

void checkText(const EditField& field, const std::string& text, const std::string& node) {
    if (text.empty()) refuse(std::string(field.name) + " must not be empty", field, node);
    checkWritable(field.name, text, node);
    if (const size_t characters = characterCount(text); characters > field.maxLength)
        refuse(std::string(field.name) + " is " + std::to_string(characters) + " characters long; at most " +
                   std::to_string(field.maxLength) + " are allowed ('" + quotedForMessage(text, 40) + "')",
               field, node);
    for (unsigned char c : text)
        if (c < 0x20 || c == 0x7f || c == '"' || c == '<' || c == '>' || c == '&')
            refuse(std::string(field.name) + " '" + quotedForMessage(text, 40) +
                       "' holds a character a name may not (a control character, \", <, > or &)",
                   field, node);
}

bool sameExtension(const std::string& name, std::string_view extension) {
    if (name.size() < extension.size()) return false;
    for (size_t i = 0; i < extension.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(name[name.size() - extension.size() + i])) != extension[i])
            return false;
    return true;
}

void checkFile(const EditField& field, const FieldValue& value, const std::string& node) {
    const auto* name = std::get_if<std::string>(&value);
    if (!name || name->empty()) return;  // a handle (checked where it is used) or none
    checkWritable(field.name, *name, node);
    for (std::string_view extension : field.extensions)
        if (sameExtension(*name, extension)) return;
    std::string list;
    for (std::string_view extension : field.extensions) list += (list.empty() ? "" : ", ") + std::string(extension);
    refuse(std::string(field.name) + ": '" + quotedForMessage(*name, 60) + "' is not an image ray reads (" + list + ")",
           field, node);
}

// The owner text of typed numbers (scene_document.h numberKey).
std::string objectKey(int id) { return "object " + std::to_string(id); }
std::string blockKey(int id) { return "block " + std::to_string(id); }

// Keeps each typed text of `input` whose number is the `values` at its place.
void keepTyped(SceneDocument& document, const FieldInput& input, const std::string& owner, const std::string& field,
               size_t first = 0) {
    for (size_t i = 0; i < input.typed.size(); ++i) {
        if (input.typed[i].empty()) continue;
        try {
            setTypedNumber(document, numberKey(owner, field, first + i), input.typed[i]);
        } catch (const InputError&) {
            // Not text a scenefile holds (JSON's "1E+2" reads, "0x1p3" does not): written in
            // the shortest form instead.
        }
    }
}

// Whether the object is alone in its transblock (the transblock's transforms are its own).
bool ownBlock(const NodePlace& place) { return place.block().items.size() == 1; }

// The transforms that place a frame as `m` does: a translate when `m` only moves, else a
// matrix (a drag's move keeps the file's translate, rotate, scale readable).
std::vector<TransformOp> asTransforms(const Affine& m) {
    constexpr double kTolerance = 1e-12;
    bool moveOnly = true;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) moveOnly = moveOnly && std::abs(m.m[r][c] - (r == c ? 1.0 : 0.0)) <= kTolerance;
    if (!moveOnly) return {TransformOp::matrix(m)};
    TransformOp move;
    move.kind = TransformKind::Translate;
    move.v = {m.m[0][3], m.m[1][3], m.m[2][3]};
    return {move};
}

// `ops` led by a move `delta` of their frame: folded into a leading translate.
std::vector<TransformOp> movedBy(std::vector<TransformOp> ops, const TransformOp& delta) {
    if (!ops.empty() && ops.front().kind == TransformKind::Translate) {
        for (size_t k = 0; k < 3; ++k) ops.front().v[k] += delta.v[k];
        return ops;
    }
    ops.insert(ops.begin(), delta);
    return ops;
}

void checkInvertible(const Affine& m, const EditField& field, const std::string& node, const std::string& what) {
    if (auto why = TransformOp::matrix(m).whySingular()) refuse(what + ": " + *why + "; it must be invertible", field, node);
}

// The object gets a transblock of its own inside the one it shares, with `ops`: it moves,
// the others stay. Returns the new transblock's id.
int giveOwnBlock(SceneDocument& document, const NodePlace& place, std::vector<TransformOp> ops) {
    Block own;
    own.id = document.nextBlockId++;
    own.transforms = std::move(ops);
    composeBlock(own);
    const int id = own.id;
    Block& shared = place.block();
    own.items.push_back(std::move(shared.items[place.index]));
    TreeNode tree;
    tree.blocks.push_back(std::move(own));
    shared.items[place.index] = Box<TreeNode>(std::move(tree));
    return id;
}

// Sets an object's or a transblock's transforms; an object sharing its transblock gets
// one of its own. Returns the transblock now holding them.
Block& setTransforms(SceneDocument& document, const NodePlace& place, std::vector<TransformOp> ops) {
    if (place.id.kind == NodeKind::Object && !ownBlock(place)) {
        giveOwnBlock(document, place, std::move(ops));
        return std::get<Box<TreeNode>>(place.block().items[place.index])->blocks[0];
    }
    Block& block = place.block();
    block.transforms = std::move(ops);
    composeBlock(block);
    return block;
}

SceneChanges moved() {
    SceneChanges changes;
    changes.geometry = true;
    changes.transformsOnly = true;
    return changes;
}

// An object's world matrix set: the transforms of its own transblock that place its first
// instance there (its other instances keep their place relative to it).
SceneChanges setWorld(SceneDocument& document, const NodePlace& place, const Affine& target, const EditField& field,
                      const FieldContext& context) {
    const std::string node = place.id.text();
    checkInvertible(target, field, node, "world");
    const int id = place.object().id;
    const auto placement = firstInstancePlacement(context.scene, id);
    const Affine worldToObject = placement ? placement->second : composedPlacement(place.blocks).second;
    if (ownBlock(place)) {
        Block& block = place.block();
        // The block takes B' = B · W⁻¹ · T, so that the first instance, P · B', is T; when B'
        // only moves B's frame (B' = Δ · B, Δ a translation), its translate takes the move.
        const Affine toParent = block.toParent * worldToObject * target;
        checkInvertible(toParent, field, node, "world, in its transblock's frame,");
        const std::vector<TransformOp> delta = asTransforms(toParent * block.fromParent);
        std::vector<TransformOp> ops = delta.front().kind == TransformKind::Translate
                                           ? movedBy(block.transforms, delta.front())
                                           : std::vector<TransformOp>{TransformOp::matrix(toParent)};
        setTransforms(document, place, std::move(ops));
        return moved();
    }
    const Affine own = worldToObject * target;
    checkInvertible(own, field, node, "world, in its transblock's frame,");
    giveOwnBlock(document, place, asTransforms(own));
    return moved();
}

TextureMap& mapOf(Material& material, SpecialField special) {
    const bool bump = special == SpecialField::BumpMap || special == SpecialField::BumpMapU ||
                      special == SpecialField::BumpMapV;
    return bump ? material.bumpMap : material.texture;
}

std::optional<ImageReference>& referenceOf(PrimitiveFiles& files, SpecialField special) {
    return special == SpecialField::Texture ? files.texture : files.bumpMap;
}

std::string& missingOf(PrimitiveFiles& files, SpecialField special) {
    return special == SpecialField::Texture ? files.missingTexture : files.missingBumpMap;
}

// An object's texture or bump map set to a file, a handle, or none ("").
SceneChanges setImage(PrimitiveNode& object, const FieldInput& input, const FieldContext& context,
                      const std::string& node) {
    const EditField& field = *input.field;
    TextureMap& map = mapOf(object.material, field.special);
    SceneChanges changes;
    changes.materials = true;
    const size_t imagesBefore = context.resources.images.size();
    if (const auto* handle = std::get_if<ImageHandle>(&input.value)) {
        if (handle->index < 0 || size_t(handle->index) >= context.resources.images.size())
            refuse(std::string(field.name) + ": texture " + std::to_string(handle->index) +
                       " does not exist; use a handle returned by its add function",
                   field, node);
        // An image read from a file is saved as its path (relative to the saved file: a part
        // of this one), which must be text XML can hold.
        const std::vector<fs::path>& files = context.resources.imageFiles;
        if (size_t(handle->index) < files.size() && files[size_t(handle->index)] != "<memory>")
            checkWritable(field.name, files[size_t(handle->index)].string(), node);
        if (object.files) {
            referenceOf(*object.files, field.special).reset();
            missingOf(*object.files, field.special).clear();
        }
        map.image = handle->index;
        return changes;
    }
    const std::string& name = std::get<std::string>(input.value);
    if (name.empty()) {
        if (object.files) {
            referenceOf(*object.files, field.special).reset();
            missingOf(*object.files, field.special).clear();
        }
        map.image = -1;
        return changes;
    }
    fs::path file;
    try {
        file = context.resolveFile(name, FileUse::Image);
    } catch (const EditError&) {
        throw;
    } catch (const std::exception& e) {
        refuse(e.what(), field, node);  // the resolver names the field (FileResolver)
    }
    loadImageInto(context.resources, file, std::string(field.name));
    PrimitiveFiles& files = object.filesToSet();
    referenceOf(files, field.special) = ImageReference{file, 0, ""};
    missingOf(files, field.special).clear();
    map.image = -1;  // the file's, found when flattened
    changes.images = context.resources.images.size() != imagesBefore;
    return changes;
}

template <class Owner, class Member>
FieldValue memberValue(const Owner& owner, Member member) {
    return FieldValue(owner.*member);
}

}  // namespace

void checkWritable(std::string_view field, const std::string& text, const std::string& node) {
    if (const std::optional<UnwritableCharacter> found = firstUnwritableCharacter(text))
        throw EditError(unwritableSentence(field, *found), EditError::Kind::Value, std::string(field), node);
}

std::optional<FieldOwner> fieldOwner(NodeKind kind) {
    switch (kind) {
        case NodeKind::Camera: return FieldOwner::Camera;
        case NodeKind::Globals: return FieldOwner::Globals;
        case NodeKind::Light: return FieldOwner::Light;
        case NodeKind::Tree: return FieldOwner::Tree;
        case NodeKind::Block: return FieldOwner::Block;
        case NodeKind::Object: return FieldOwner::Object;
        case NodeKind::Placement:
        case NodeKind::Csg: return std::nullopt;
    }
    return std::nullopt;
}

std::vector<const EditField*> fieldsFor(const SceneDocument& document, const NodePlace& place) {
    const std::optional<FieldOwner> owner = fieldOwner(place.id.kind);
    if (!owner) return {};
    std::vector<const EditField*> fields = fieldsOf(*owner);
    if (place.id.kind == NodeKind::Light) {
        const LightType type = document.lights[place.index].type;
        std::erase_if(fields, [&](const EditField* f) { return !f->appliesTo(type); });
    }
    return fields;
}

std::optional<std::pair<Affine, Affine>> firstInstancePlacement(const Scene& scene, int id) {
    for (const auto* list : {&scene.primitives, &scene.csgOperands})
        for (const PrimitiveInstance& instance : *list)
            if (instance.type != PrimitiveType::Csg && instance.sourceObject == id)
                return std::pair{instance.objectToWorld, instance.worldToObject};
    return std::nullopt;
}

FieldValue fieldValue(const SceneDocument& document, const Scene& scene, const NodePlace& place,
                      const EditField& field) {
    const bool objectField = place.id.kind == NodeKind::Object;
    switch (field.special) {
        case SpecialField::None: break;
        case SpecialField::Texture:
        case SpecialField::BumpMap: {
            const PrimitiveNode& object = place.object();
            if (object.files) {
                PrimitiveFiles& files = *object.files;
                if (const auto& reference = referenceOf(files, field.special)) {
                    if (!reference->written.empty()) return reference->written;
                    return reference->file.lexically_proximate(document.file.parent_path()).generic_string();
                }
                if (!missingOf(files, field.special).empty()) return missingOf(files, field.special);
            }
            const TextureMap& map = field.special == SpecialField::Texture ? object.material.texture
                                                                           : object.material.bumpMap;
            if (map.image >= 0) return ImageHandle{map.image};
            return std::string();
        }
        case SpecialField::TextureU:
        case SpecialField::BumpMapU: return mapOf(place.object().material, field.special).repeatU;
        case SpecialField::TextureV:
        case SpecialField::BumpMapV: return mapOf(place.object().material, field.special).repeatV;
        case SpecialField::Transforms:
            if (objectField && !ownBlock(place)) return std::vector<TransformOp>{};
            return place.block().transforms;
        case SpecialField::World: {
            const auto placement = firstInstancePlacement(scene, place.object().id);
            return placement ? placement->first : composedPlacement(place.blocks).first;
        }
        case SpecialField::LightType: return std::string(lightTypeName(document.lights[place.index].type));
        case SpecialField::TreeName: return place.tree->name;
    }
    return std::visit(
        [&](auto member) -> FieldValue {
            using M = decltype(member);
            if constexpr (std::is_same_v<M, std::monostate>) return 0.0;
            else if constexpr (std::is_same_v<M, Vec3 Material::*> || std::is_same_v<M, double Material::*>)
                return memberValue(place.object().material, member);
            else if constexpr (std::is_same_v<M, Vec3 Light::*> || std::is_same_v<M, double Light::*>)
                return memberValue(document.lights[place.index], member);
            else if constexpr (std::is_same_v<M, Vec3 Camera::*> || std::is_same_v<M, double Camera::*>)
                return memberValue(document.camera, member);
            else return memberValue(document.globals, member);
        },
        field.member);
}

void checkFieldValue(const FieldInput& input, const std::string& node) {
    const EditField& field = *input.field;
    if (!holdsKind(input.value, field.kind))
        refuse(std::string(field.name) + " takes " + kindPhrase(field.kind), field, node, EditError::Kind::Type);
    switch (field.kind) {
        case FieldKind::Number: checkRule(field, brokenRule(field.name, std::get<double>(input.value), *field.rule), node); break;
        case FieldKind::Color:
        case FieldKind::Vector: {
            const Vec3 v = std::get<Vec3>(input.value);
            checkRule(field, brokenRule(field.name, v, *field.rule), node);
            if (field.nonzero && v == Vec3{0, 0, 0})
                refuse(std::string(field.name) + " (0, 0, 0) has no direction; give a non-zero one", field, node);
            break;
        }
        case FieldKind::Choice: {
            const std::string& choice = std::get<std::string>(input.value);
            bool known = false;
            std::string list;
            for (std::string_view c : field.choices) {
                known = known || c == choice;
                list += (list.empty() ? "" : ", ") + std::string(c);
            }
            if (!known)
                refuse(std::string(field.name) + " is one of " + list + ", not '" + quotedForMessage(choice, 40) + "'",
                       field, node);
            break;
        }
        case FieldKind::Text: checkText(field, std::get<std::string>(input.value), node); break;
        case FieldKind::File: checkFile(field, input.value, node); break;
        case FieldKind::Transforms: checkTransforms(field, std::get<std::vector<TransformOp>>(input.value), node); break;
        case FieldKind::Matrix: {
            const Affine& m = std::get<Affine>(input.value);
            checkTransforms(field, {TransformOp::matrix(m)}, node);
            break;
        }
    }
}

SceneChanges setField(SceneDocument& document, const NodePlace& place, const FieldInput& input,
                      const FieldContext& context) {
    const std::string node = place.id.text();
    checkFieldValue(input, node);
    const EditField& field = *input.field;
    SceneChanges changes;
    switch (field.special) {
        case SpecialField::None: break;
        case SpecialField::Texture:
        case SpecialField::BumpMap: return setImage(place.object(), input, context, node);
        case SpecialField::TextureU:
        case SpecialField::TextureV:
        case SpecialField::BumpMapU:
        case SpecialField::BumpMapV: {
            const bool u = field.special == SpecialField::TextureU || field.special == SpecialField::BumpMapU;
            TextureMap& map = mapOf(place.object().material, field.special);
            (u ? map.repeatU : map.repeatV) = std::get<double>(input.value);
            const bool texture = field.special == SpecialField::TextureU || field.special == SpecialField::TextureV;
            keepTyped(document, input, objectKey(place.object().id), texture ? "texture" : "bumpmap", u ? 0 : 1);
            changes.materials = true;
            return changes;
        }
        case SpecialField::Transforms: {
            const Block& block = setTransforms(document, place, std::get<std::vector<TransformOp>>(input.value));
            size_t first = 0;
            for (size_t i = 0; i < block.transforms.size(); ++i) {
                const size_t count = numbersOf(block.transforms[i].kind);
                FieldInput part{input.field, input.value, {}};
                for (size_t k = first; k < first + count && k < input.typed.size(); ++k) part.typed.push_back(input.typed[k]);
                keepTyped(document, part, blockKey(block.id), "transform " + std::to_string(i));
                first += count;
            }
            return moved();
        }
        case SpecialField::World: return setWorld(document, place, std::get<Affine>(input.value), field, context);
        case SpecialField::LightType: {
            const std::string& name = std::get<std::string>(input.value);
            for (size_t t = 0; t < lightTypeNames().size(); ++t)
                if (lightTypeNames()[t] == name) document.lights[place.index].type = LightType(t);
            changes.lights = true;
            return changes;
        }
        case SpecialField::TreeName: {
            const std::string& name = std::get<std::string>(input.value);
            if (name == place.tree->name) return changes;
            if (document.trees.count(name))
                throw EditError("there is already a tree named '" + quotedForMessage(name, 60) + "'",
                                EditError::Kind::Exists, "name", node);
            try {
                const std::string from = place.tree->name;  // a copy: renameTree moves the tree
                renameTree(document, from, name);
            } catch (const InputError& e) {
                refuse(std::string(e.what()).substr(std::string_view(e.what()).starts_with("error: ") ? 7 : 0), field,
                       node);
            }
            return changes;  // the flattened scene is the same
        }
    }
    std::visit(
        [&](auto member) {
            using M = decltype(member);
            if constexpr (std::is_same_v<M, std::monostate>) {
            } else if constexpr (std::is_same_v<M, Vec3 Material::*> || std::is_same_v<M, double Material::*>) {
                place.object().material.*member = std::get<std::remove_reference_t<decltype(place.object().material.*member)>>(input.value);
                keepTyped(document, input, objectKey(place.object().id), std::string(field.name));
                changes.materials = true;
            } else if constexpr (std::is_same_v<M, Vec3 Light::*> || std::is_same_v<M, double Light::*>) {
                Light& light = document.lights[place.index];
                light.*member = std::get<std::remove_reference_t<decltype(light.*member)>>(input.value);
                keepTyped(document, input, "light " + std::to_string(place.index), std::string(field.name));
                changes.lights = true;
            } else if constexpr (std::is_same_v<M, Vec3 Camera::*> || std::is_same_v<M, double Camera::*>) {
                document.camera.*member = std::get<std::remove_reference_t<decltype(document.camera.*member)>>(input.value);
                keepTyped(document, input, "camera", std::string(field.name));
                changes.camera = true;
            } else {
                document.globals.*member = std::get<double>(input.value);
                keepTyped(document, input, "globals", std::string(field.name));
                changes.globals = true;
            }
        },
        field.member);
    return changes;
}

void loadImageInto(Resources& resources, const fs::path& file, const std::string& field) {
    std::error_code ignored;
    fs::path key = fs::weakly_canonical(file, ignored);
    if (key.empty()) key = file;
    auto known = resources.imageIndex.find(key);
    if (known != resources.imageIndex.end() && known->second >= 0) return;
    Image image;
    try {
        image = readImage(key);
    } catch (const std::exception& e) {
        throw EditError(field + ": '" + quotedForMessage(file.filename().string(), 60) + "' cannot be read as an image (" +
                            quotedForMessage(e.what()) + ")",
                        EditError::Kind::Value, field);
    }
    resources.images.push_back(std::move(image));
    resources.imageFiles.push_back(key);
    resources.imageIndex[key] = int(resources.images.size()) - 1;
}

void loadMeshInto(Resources& resources, const fs::path& file, const std::string& field) {
    std::error_code ignored;
    fs::path key = fs::weakly_canonical(file, ignored);
    if (key.empty()) key = file;
    auto known = resources.meshIndex.find(key);
    if (known != resources.meshIndex.end() && known->second >= 0) return;
    TriangleMesh mesh;
    try {
        mesh = loadObjMesh(key);
    } catch (const std::exception& e) {
        throw EditError(field + ": '" + quotedForMessage(file.filename().string(), 60) + "' cannot be read as a mesh (" +
                            quotedForMessage(e.what()) + ")",
                        EditError::Kind::Value, field);
    }
    resources.meshes.push_back(std::move(mesh));
    resources.meshFiles.push_back(key);
    resources.meshIndex[key] = int(resources.meshes.size()) - 1;
}

}  // namespace ray::edit
