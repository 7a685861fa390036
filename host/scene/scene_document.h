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
// (PrimitiveInstance::sourceObject). The editor's other nodes have ids as stable, from
// SceneDocument::nextNodeId: every top-level tree, master placement, csg object and light
// (assignNodeIds gives them to a document that lacks them).
//
// Masters. An object inside a master is one element however many times the master is
// placed: editing its material or its transform edits the master, so every instance
// changes, as editing a component's definition does in a modeler. Its transform is set
// as the object-to-world of its first instance (in flattening order); the others keep
// their place relative to it.
//
// Transforms are kept as written (translate, rotate, scale, matrix, in order) next to their
// composition, so that a saved file composes, on loading, to the very same bits.
//
// Text. A document read from a file keeps the file's text (SceneDocument::source), and
// each of its nodes the element it was read from (a SourceId; kNoSource for what was made
// in code). Saving writes that text with splices for what the document now says
// differently (document_splices.h): a document saved unedited is its file, byte for byte,
// and an edit changes the lines of what it touched alone. Edits need not say what they
// changed in the text: they change the document, and the save compares it with the text.
// A document with no text (made in code) is written afresh (canonical_writer.h).
// A document read from a course JSON scene keeps its text as a JsonSource instead
// (json_splices.h: its nodes' SourceIds are JSON values), and is saved as JSON the same way.
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
#include "scene/source_text.h"

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
    std::string written;  // the reference as the file writes it; empty when set in code
};

// What few primitives name, kept apart so that the common primitive stays small (a large
// flat scene holds 10^5 of them).
struct PrimitiveFiles {
    std::optional<ImageReference> texture, bumpMap;
    // A texture or bump map named but not found (a warning at loading): kept as written
    // so that saving does not lose it.
    std::string missingTexture, missingBumpMap;
    std::filesystem::path meshFile;  // resolved; meshes only
    std::string meshWritten;         // meshFile as the file writes it; empty when set in code
};

// <object type="primitive">.
struct PrimitiveNode {
    PrimitiveType type = PrimitiveType::Cube;
    int line = 0;  // in the file it was read from; 0 when made in code
    int id = -1;   // stable (see above)
    SourceId source = kNoSource;  // its element in the document's text
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
    SourceId source = kNoSource;
    int id = -1;  // stable (see above)
};

using SceneItem = std::variant<PrimitiveNode, Box<TreeNode>, MasterReference, Box<CsgNode>>;

// <transblock>.
struct Block {
    int id = -1;                          // stable (see above)
    // Its <transblock>; kNoSource for one made in code, or for a bare <object> in a tree
    // or a csg (bare: the block the loader puts it in, which the file does not write).
    SourceId source = kNoSource;
    bool bare = false;
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
    // Its <object type="tree"> (a top-level tree's or an inline one's); kNoSource for a
    // csg operand (its block is its element) and what was made in code.
    SourceId source = kNoSource;
};

// <object type="csg" operation="..."> (scene/csg.h): each operand is written as a tree's
// children are, one <transblock> (or one bare <object>) per operand.
struct CsgNode {
    CsgStepKind operation = CsgStepKind::Union;
    int line = 0;
    SourceId source = kNoSource;
    std::vector<TreeNode> operands;
    int id = -1;  // stable (see above)
};

// A top-level <object type="tree" name="...">.
struct NamedTree {
    enum class State { Uncounted, Counting, Counted };
    std::string name;
    int id = -1;  // stable (see above): a rename keeps it
    int line = 0;
    TreeNode tree;
    // Set by the count pass.
    State state = State::Uncounted;
    uint64_t instances = 0;
    int levels = 0;  // how deep trees and masters nest inside it
};

// The two formats of a scene file: the CS123 XML (SPEC §1) and the course's JSON (SPEC §7).
enum class SceneFormat : uint8_t { Xml, Json };

struct JsonSource;

struct SceneDocument {
    std::filesystem::path file;  // the file it was read from (relative paths are found from its folder)
    SceneFormat format = SceneFormat::Xml;  // of the file it was read from
    GlobalCoefficients globals;
    Camera camera;
    std::vector<Light> lights;
    std::map<std::string, NamedTree> trees;  // by name
    std::vector<std::string> treeOrder;      // the trees' names in the file's order
    int scenefileLine = 0;
    size_t primitiveElements = 0;  // <object type="primitive"> elements read
    int nextObjectId = 0, nextBlockId = 0;
    // The ids of trees, placements, csg objects and lights (lightIds, in the order of
    // `lights`; addLight and removeLight keep the two in step).
    int nextNodeId = 0;
    std::vector<int> lightIds;

    // The file's text (null for a document made in code) and, in the order of `lights`,
    // the <lightdata> each light was read from (lights past its end were added in code;
    // removeLight, below, keeps the two in step).
    std::shared_ptr<const SourceText> source;
    std::vector<SourceId> lightSources;
    // Numbers as the user typed them, by field (numberKey, below; setTypedNumber sets
    // one): a save writes a changed number with this text when the text reads as the
    // number the field holds, in the shortest form that reads back as it otherwise.
    std::map<std::string, std::string> typedNumbers;
    // A JSON document's text (format Json; null for XML and for a document made in code):
    // the text, its values and the document as it reads (json_splices.h).
    std::shared_ptr<const JsonSource> jsonSource;

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

// Gives every tree, master placement, csg object and light that has no id one (loading
// does, so that the editor can name them).
void assignNodeIds(SceneDocument& document);

// The top-level trees in the file's order, then those made in code.
std::vector<NamedTree*> treesInOrder(SceneDocument& document);

// The place of object `id`, of transblock `id`; nullopt when there is none (removed).
std::optional<DocumentPlace> findObject(SceneDocument& document, int id);
std::optional<DocumentPlace> findBlock(SceneDocument& document, int id);

// Calls visit(node, place) for every primitive element, in document order.
void forEachObject(SceneDocument& document, const std::function<void(PrimitiveNode&, const DocumentPlace&)>& visit);
void forEachBlock(SceneDocument& document, const std::function<void(Block&, const DocumentPlace&)>& visit);

// The composed transform of `blocks` (outermost first), from their tree's frame down,
// as flattening composes it: {to the tree's frame, from it}.
std::pair<Affine, Affine> composedPlacement(const std::vector<Block*>& blocks);

// The key of a number in SceneDocument::typedNumbers: `owner` is "object ID", "light
// INDEX", "camera", "globals" or "block ID"; `field` the element that writes it
// ("diffuse", "pos", "ambientcoeff", "transform I" for a block's I-th transform, "motion",
// "texture" and "bumpmap" for their repeats), `index` the number's place in the element.
std::string numberKey(const std::string& owner, const std::string& field, size_t index);
// The text a save writes for a number: the typed text under `key` when it reads as
// `value`, bit for bit; the shortest text that reads back as `value` otherwise.
std::string typedNumberText(const SceneDocument& document, const std::string& key, double value);

// A light added after the others (one made in code: a save writes it afresh), with an id of
// its own (lightIds); returns its index. removeLight takes the light and the element it was read from (a save removes
// that element): lights are removed through it, never from SceneDocument::lights alone.
// Throws InputError for an index out of range.
size_t addLight(SceneDocument& document, const Light& light);
void removeLight(SceneDocument& document, size_t index);

// The number under `key` (numberKey) is written as `text` by saves while the field holds
// the value `text` reads as. Throws InputError when `text` is not a plain finite number.
void setTypedNumber(SceneDocument& document, const std::string& key, const std::string& text);

// The scenefile text of the document, in UTF-8, which loads back to the same scene, in the
// format `target`'s name says (.json: the course's JSON, SPEC §7; .xml: SPEC §1's XML; any
// other name: the document's own). A document that keeps its file's text, saved in its
// format, is that text with splices for what it now says differently (document_splices.h):
// unedited, the file byte for byte (for a file in UTF-8; a file in another encoding is its
// text in UTF-8, its declaration kept: see documentFileBytes). One made in code, or saved in
// the other format, is written whole (canonical_writer.h, json_writer.h: what JSON cannot
// hold, such as a torus, is refused with its line). A JSON document read from a file, saved
// as JSON, is its text with splices likewise (json_splices.h). Texture and mesh paths the document changed, and all of them when `target` is in another folder than
// the file, are written relative to `target`'s folder. Throws InputError for what a file
// cannot hold (a texture or mesh made in memory, a name with a character XML cannot hold:
// scene/xml_characters.h).
std::string documentToText(const SceneDocument& document, const Resources& resources,
                           const std::filesystem::path& target);

// The bytes of the file documentToText's text makes: in the encoding of the file the
// document was read from (scene/text_encoding.h: ISO-8859-1, US-ASCII and UTF-16 files stay
// so, a character the encoding lacks written as a reference &#x...;), the file's very bytes
// when nothing changed. Throws as documentToText.
std::string documentFileBytes(const SceneDocument& document, const Resources& resources,
                              const std::filesystem::path& target);

// documentFileBytes, read back as a fresh load of `target` would read them (the loader's
// every rule) and then written to `target` atomically (core/atomic_file.h). Bytes that would
// not load, or load as another scene (its trees' names, its objects or lights), are
// refused with the reason, and `target` is left as it was. Throws InputError, or
// FileWriteError.
void saveDocument(const SceneDocument& document, const Resources& resources, const std::filesystem::path& target);

}  // namespace ray
