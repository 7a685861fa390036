// The scene as its file has it: the scene document.
//
// A CS123 scenefile is a tree: top-level named trees (the one named "root" is the scene,
// the others are masters), each a list of <transblock>s holding transforms and objects
// (primitives, inline trees, references to masters, csg objects). The loader parses a
// file into a SceneDocument, and flattening (scene_loader.h, flattenDocument) turns a
// document into the flat Scene the renderers take; the public API keeps the document,
// edits it, re-flattens it, and saves it (documentToText, saveDocument), so the loader,
// the API and the saver share this one model.
//
// Identity. Every primitive element (<object type="primitive">) has a stable id, unique
// in its document for the document's life (SceneDocument::nextObjectId hands them out;
// a removed object's id is never reused), and so has every <transblock> (Block::id). Each
// flattened PrimitiveInstance names the primitive element it came from
// (PrimitiveInstance::sourceObject).
//
// Masters. An object inside a master is one element however many times the master is
// placed: editing its material or its transform edits the master, so every instance
// changes, as editing a component's definition does in a modeler. Its transform is set
// as the object-to-world of its first instance (in flattening order); the others keep
// their place relative to it.
//
// Transforms are kept as written (translate, rotate, scale, matrix, in order) next to their
// composition, so that a saved file composes, on loading, to the very same bits.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/math.h"
#include "scene/csg.h"
#include "scene/scene.h"

namespace ray {

// A value-semantic owning pointer: copying it copies what it points to. The document's
// recursive parts (inline trees, csg objects) are boxed so that a document copies deep.
template <class T>
class Box {
public:
    Box() = default;
    explicit Box(std::unique_ptr<T> p) : p_(std::move(p)) {}
    explicit Box(T value) : p_(std::make_unique<T>(std::move(value))) {}
    Box(const Box& other) : p_(other.p_ ? std::make_unique<T>(*other.p_) : nullptr) {}
    Box& operator=(const Box& other) {
        if (this != &other) p_ = other.p_ ? std::make_unique<T>(*other.p_) : nullptr;
        return *this;
    }
    Box(Box&&) noexcept = default;
    Box& operator=(Box&&) noexcept = default;

    explicit operator bool() const { return bool(p_); }
    T& operator*() const { return *p_; }
    T* operator->() const { return p_.get(); }
    T* get() const { return p_.get(); }

private:
    std::unique_ptr<T> p_;
};

// One transform element of a <transblock>, as written.
enum class TransformKind : uint8_t { Translate, Rotate, Scale, Matrix };

struct TransformOp {
    TransformKind kind = TransformKind::Translate;
    // Translate and scale: x y z in v[0..2]; rotate: the axis in v[0..2], the angle in
    // degrees in v[3]; matrix: its first three rows, row-major, in v[0..11].
    std::array<double, 12> v{};

    static TransformOp matrix(const Affine& m);
    // The transform and its exact inverse (the inverse of a matrix is computed; NaNs when
    // it is singular).
    std::pair<Affine, Affine> affine() const;
    // Why the transform flattens what it holds (a zero rotation axis, a zero scale, a
    // singular matrix): the one rule the loader, the API and the viewer's edits refuse
    // with; nullopt when it is invertible.
    std::optional<std::string> whySingular() const;
};

// A texture or bump map file, resolved, and the line that names it.
struct ImageReference {
    std::filesystem::path file;
    int line = 0;
};

// What few primitives name, kept apart so that the common primitive stays small (a large
// flat scene holds 10^5 of them).
struct PrimitiveFiles {
    std::optional<ImageReference> texture, bumpMap;
    // A texture or bump map named but not found (a warning at loading): kept as written
    // so that saving does not lose it.
    std::string missingTexture, missingBumpMap;
    std::filesystem::path meshFile;  // resolved; meshes only
};

// <object type="primitive">.
struct PrimitiveNode {
    PrimitiveType type = PrimitiveType::Cube;
    int line = 0;  // in the file it was read from; 0 when made in code
    int id = -1;   // stable (see above)
    // Its texture and bump map images are the files' (files) when it names any; otherwise
    // material.texture.image / bumpMap.image index Resources::images (objects made in
    // code), or are -1.
    Material material;
    int mesh = -1;          // Resources index of a mesh made in code (files->meshFile otherwise)
    Box<PrimitiveFiles> files;  // null when it names none

    PrimitiveFiles& filesToSet() {
        if (!files) files = Box<PrimitiveFiles>(std::make_unique<PrimitiveFiles>());
        return *files;
    }
};

struct TreeNode;
struct NamedTree;
struct CsgNode;

// <object type="master" name="...">.
struct MasterReference {
    std::string name;
    int line = 0;
    NamedTree* target = nullptr;  // set by the count pass (and after a document is copied)
};

using SceneItem = std::variant<PrimitiveNode, Box<TreeNode>, MasterReference, Box<CsgNode>>;

// <transblock>.
struct Block {
    int id = -1;                          // stable (see above)
    std::vector<TransformOp> transforms;  // as written, in order (empty in a document only flattened)
    Affine toParent;    // T1 · T2 · … · Tn (composeBlock)
    Affine fromParent;  // its inverse, composed from the exact inverses of each Ti
    Vec3 motion;        // <motion>: the end-of-shutter displacement, in the parent's frame
    std::vector<SceneItem> items;
};

// Sets the block's toParent and fromParent from its transforms (the loader and the edits
// compose alike, so a saved file composes to the same bits on loading).
void composeBlock(Block& block);

struct TreeNode {
    std::vector<Block> blocks;
};

// <object type="csg" operation="..."> (scene/csg.h): each operand is written as a tree's
// children are, one <transblock> (or one bare <object>) per operand.
struct CsgNode {
    CsgStepKind operation = CsgStepKind::Union;
    int line = 0;
    std::vector<TreeNode> operands;
};

// A top-level <object type="tree" name="...">.
struct NamedTree {
    enum class State { Uncounted, Counting, Counted };
    std::string name;
    int line = 0;
    TreeNode tree;
    // Set by the count pass.
    State state = State::Uncounted;
    uint64_t instances = 0;
    int levels = 0;  // how deep trees and masters nest inside it
};

struct SceneDocument {
    std::filesystem::path file;  // the file it was read from (relative paths are found from its folder)
    GlobalCoefficients globals;
    Camera camera;
    std::vector<Light> lights;
    std::map<std::string, NamedTree> trees;  // by name
    std::vector<std::string> treeOrder;      // the trees' names in the file's order
    int scenefileLine = 0;
    size_t primitiveElements = 0;  // <object type="primitive"> elements read
    int nextObjectId = 0, nextBlockId = 0;

    SceneDocument() = default;
    SceneDocument(const SceneDocument& other);  // deep, masters resolved in the copy
    SceneDocument& operator=(const SceneDocument& other);
    SceneDocument(SceneDocument&&) noexcept = default;
    SceneDocument& operator=(SceneDocument&&) noexcept = default;

    // Points every master reference at its tree (nullptr when none has its name).
    void resolveMasters();
    // The tree named "root", made (empty, last) when the document has none.
    NamedTree& rootToSet();
};

// Images and meshes, each file loaded once. Kept beside a document, not in it: a document
// is copied for every edit, and its images are not. Scene::images and Scene::meshes are
// copies of these, with the same indices.
struct Resources {
    std::vector<Image> images;
    std::vector<std::filesystem::path> imageFiles;  // "<memory>" for images made in code
    std::vector<TriangleMesh> meshes;
    std::vector<std::filesystem::path> meshFiles;  // "<memory>" for meshes made in code
    std::map<std::filesystem::path, int> imageIndex, meshIndex;  // by canonical path; -1: unreadable
};

// Where a primitive element or a transblock sits in its document.
struct DocumentPlace {
    NamedTree* tree = nullptr;           // the top-level tree holding it
    std::vector<Block*> blocks;          // the blocks enclosing it, outermost first
    Block* block = nullptr;              // its own block (for a transblock: itself)
    size_t item = 0;                     // its index in block->items (objects only)
    std::string path;                    // "root/transblock[1]/object[0]" ("gear/..." in a master)
};

// The place of object `id`, of transblock `id`; nullopt when there is none (removed).
std::optional<DocumentPlace> findObject(SceneDocument& document, int id);
std::optional<DocumentPlace> findBlock(SceneDocument& document, int id);

// Calls visit(node, place) for every primitive element, in document order.
void forEachObject(SceneDocument& document, const std::function<void(PrimitiveNode&, const DocumentPlace&)>& visit);
void forEachBlock(SceneDocument& document, const std::function<void(Block&, const DocumentPlace&)>& visit);

// The composed transform of `blocks` (outermost first), from their tree's frame down,
// as flattening composes it: {to the tree's frame, from it}.
std::pair<Affine, Affine> composedPlacement(const std::vector<Block*>& blocks);

// The scenefile text of the document (SPEC §1), which loads back to the same scene.
// Texture and mesh paths are written relative to `target`'s folder. Throws InputError
// for what a file cannot hold (a texture or mesh made in memory).
std::string documentToText(const SceneDocument& document, const Resources& resources,
                           const std::filesystem::path& target);

// documentToText, written to `target` atomically (core/atomic_file.h). Throws InputError,
// or FileWriteError.
void saveDocument(const SceneDocument& document, const Resources& resources, const std::filesystem::path& target);

}  // namespace ray
