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
#include <string_view>
#include <variant>
#include <vector>

#include "core/message_text.h"
#include "scene/csg.h"
#include "scene/scene_document.h"
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
    // `file` as messages name it: long names cut, control characters escaped.
    Diagnostics(std::string_view file, const LoadOptions& options) : file_(quotedForMessage(file)), options_(options) {}

    // "file: error: problem; remedy", for a problem with no line (the file cannot be read).
    [[noreturn]] void fileError(const std::string& problem, const std::string& remedy) const {
        error(0, problem, remedy);
    }

    // `problem` says what is wrong, `remedy` what to do about it. A column (JSON files:
    // where the key or value starts) follows the line when given.
    [[noreturn]] void error(int line, const std::string& problem, const std::string& remedy, int column = 0) const {
        throw InputError(where(line, column) + "error: " + problem + "; " + remedy);
    }

    void warning(int line, const std::string& message, int column = 0) const {
        if (options_.strict)
            throw InputError(where(line, column) + "error: " + message + " (strict mode turns warnings into errors)");
        std::string text = where(line, column) + "warning: " + message;
        if (options_.warn)
            options_.warn(text);
        else
            std::cerr << text << std::endl;
    }

    const LoadOptions& options() const { return options_; }

private:
    std::string where(int line, int column) const {
        if (line <= 0) return file_ + ": ";
        std::string text = file_ + ":" + std::to_string(line);
        if (column > 0) text.append(":").append(std::to_string(column));  // not ":" + string&&: GCC 12 warns (-Wrestrict)
        return text + ": ";
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
// The parsed scene graph: the scene document (scene/scene_document.h)

using ray::Block;
using ray::Box;
using ray::CsgNode;
using ray::ImageReference;
using ray::MasterReference;
using ray::NamedTree;
using ray::PrimitiveFiles;
using ray::PrimitiveNode;
using ray::Resources;
using ray::SceneDocument;
using ray::SceneItem;
using ray::TreeNode;

// ---------------------------------------------------------------------------------------
// The passes

// Pass 1 (scene_loader_parse.cpp): the XML into `document`: its globals, camera, lights
// and the graph of its top-level trees, every rule checked. Without keepTransforms each
// block keeps only its composition, not its transforms as written: what flattening needs
// and not what saving does (a flat scene of 10^5 blocks loads in half the memory).
void parseSceneDocument(XmlElement root, const Diagnostics& diagnostics, const FileSearch& search,
                        SceneDocument& document, bool keepTransforms = true);

// File references, as both readers report them (scene_loader_parse.cpp): where a search
// looked (the path as given, then the roots its trailing parts were tried under), and the
// first candidate that exists but is no regular file (a FIFO, a folder), which deserves its
// own message rather than "not found".
std::string whereLooked(const std::string& reference, const std::vector<fs::path>& tried, const FileSearch& search);
std::optional<fs::path> firstNonRegular(const std::vector<fs::path>& tried);

// Pass 2 (scene_loader_count.cpp): every top-level tree's instance count and nesting
// levels, masters resolved to their trees; a missing master, a cycle or nesting beyond
// kMaxNestingLevels is an error. Counts afresh each time (the document may have changed).
void countInstances(std::map<std::string, NamedTree>& trees, const Diagnostics& diagnostics);

// Pass 3 (scene_loader_flatten.cpp): the instances of `root` into `scene`, with their
// materials; images and meshes are loaded into `resources` on first use (once per file),
// and scene.images and scene.meshes are left for the caller to fill from it.
void flattenScene(TreeNode& root, const Diagnostics& diagnostics, const LoadOptions& options, Resources& resources,
                  Scene& scene);

// Passes 2 and 3 over a parsed or edited document, with the limits (LoadOptions::
// maxPrimitives, the host's memory) checked between them.
Scene flattenWithDiagnostics(SceneDocument& document, Resources& resources, const Diagnostics& diagnostics,
                             const LoadOptions& options);

}  // namespace ray::loader
