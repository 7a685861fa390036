// The three passes of the scene loader (scene_loader.cpp describes them) and what they
// share: the messages and the parsed scene graph. Internal to the loader.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "scene/csg.h"
#include "scene/file_search.h"
#include "scene/scene_loader.h"
#include "scene/xml_tree.h"

namespace ray::loader {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Messages

// Formats errors and warnings as "<file>:<line>: error: ..." and routes warnings to the
// caller (or stderr); with the strict option a warning is thrown as an error instead.
class Diagnostics {
public:
    Diagnostics(std::string file, const LoadOptions& options) : file_(std::move(file)), options_(options) {}

    // `problem` says what is wrong, `remedy` what to do about it.
    [[noreturn]] void error(int line, const std::string& problem, const std::string& remedy) const {
        throw InputError(where(line) + "error: " + problem + "; " + remedy);
    }

    void warning(int line, const std::string& message) const {
        if (options_.strict)
            throw InputError(where(line) + "error: " + message + " (strict mode turns warnings into errors)");
        std::string text = where(line) + "warning: " + message;
        if (options_.warn)
            options_.warn(text);
        else
            std::cerr << text << std::endl;
    }

private:
    std::string where(int line) const {
        return line > 0 ? file_ + ":" + std::to_string(line) + ": " : file_ + ": ";
    }

    std::string file_;
    const LoadOptions& options_;
};

// The items with `separator` between them (a cycle of masters, the names of the trees).
inline std::string joined(const std::vector<std::string>& items, const char* separator) {
    std::string result;
    for (const std::string& item : items) result += (result.empty() ? "" : separator) + item;
    return result;
}

// ---------------------------------------------------------------------------------------
// The parsed scene graph

// A texture or bump map file, resolved, and the line that names it.
struct ImageReference {
    fs::path file;
    int line = 0;
};

// What few primitives name, kept apart so that the common primitive stays small (a large
// flat scene holds 10^5 of them).
struct PrimitiveFiles {
    std::optional<ImageReference> texture, bumpMap;
    fs::path meshFile;  // resolved; meshes only
};

struct PrimitiveNode {
    PrimitiveType type = PrimitiveType::Cube;
    int line = 0;
    Material material;  // image indices filled in on first use
    std::unique_ptr<PrimitiveFiles> files;  // null when it names none
    // Indices into the Scene, set when the first instance is made.
    int sceneMaterial = -1;
    int sceneMesh = -1;

    PrimitiveFiles& filesToSet() {
        if (!files) files = std::make_unique<PrimitiveFiles>();
        return *files;
    }
};

struct TreeNode;
struct NamedTree;

struct MasterReference {
    std::string name;
    int line = 0;
    NamedTree* target = nullptr;  // set by the count pass
};

struct CsgNode;

using SceneItem = std::variant<PrimitiveNode, std::unique_ptr<TreeNode>, MasterReference, std::unique_ptr<CsgNode>>;

struct Block {
    Affine toParent;    // T1 · T2 · … · Tn
    Affine fromParent;  // its inverse, composed from the exact inverses of each Ti
    Vec3 motion;        // <motion>: the end-of-shutter displacement, in the parent's frame
    std::vector<SceneItem> items;
};

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

struct NamedTree {
    enum class State { Uncounted, Counting, Counted };
    std::string name;
    int line = 0;
    TreeNode tree;
    State state = State::Uncounted;
    uint64_t instances = 0;
    int levels = 0;  // how deep trees and masters nest inside it (set by the count pass)
};

// ---------------------------------------------------------------------------------------
// The passes

// Pass 1 (scene_loader_parse.cpp): the document into the scene's globals, camera and
// lights (written to `scene`) and the graph of its top-level trees, every rule checked.
struct ParsedScene {
    std::map<std::string, NamedTree> trees;  // by name
    size_t primitiveElements = 0;            // <object type="primitive"> elements read
};
ParsedScene parseSceneDocument(XmlElement root, const Diagnostics& diagnostics, const FileSearch& search,
                               Scene& scene);

// Pass 2 (scene_loader_count.cpp): every top-level tree's instance count and nesting
// levels, masters resolved to their trees; a missing master, a cycle or nesting beyond
// kMaxNestingLevels is an error.
void countInstances(std::map<std::string, NamedTree>& trees, const Diagnostics& diagnostics);

// Pass 3 (scene_loader_flatten.cpp): the instances of `root` into `scene`, with their
// materials, images and meshes, each loaded once.
void flattenScene(TreeNode& root, const Diagnostics& diagnostics, const LoadOptions& options, Scene& scene);

}  // namespace ray::loader
