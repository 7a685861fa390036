// Reading a CS123 scenefile (SPEC §1) into a flattened Scene.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"
#include "scene/scene_document.h"

namespace ray {

// How deep inline trees and masters may nest. Counting and flattening recurse once per
// level; a chain of 100000 masters overflowed the stack (tests/data/limits/).
constexpr int kMaxNestingLevels = 1000;

// How deep XML elements may nest (XmlTree refuses deeper ones). The parse pass recurses
// per element; one level of inline tree is two elements (<object>, <transblock>), so
// inline trees can reach kMaxNestingLevels, whose message speaks of trees, before this.
constexpr int kMaxElementDepth = 2 * kMaxNestingLevels + 8;

struct LoadOptions {
    // Extra roots for file references, searched first (--search-path, then RAY_SEARCH_PATH).
    std::vector<std::filesystem::path> searchPaths;
    // Every warning becomes an error (--strict).
    bool strict = false;
    // Load texture and bump-map images (off for --no-textures, and for tests of the parser).
    bool loadImages = true;
    // Refuse scenes that flatten to more primitive instances than this, before flattening.
    size_t maxPrimitives = 50'000'000;
    // Receives each warning, complete ("scene.xml:7: warning: ..."). Default: stderr.
    std::function<void(const std::string&)> warn;
};

// The format of a scene file: by its text's first character after blanks and a byte-order
// mark ('{' or '[': JSON; '<': XML), else (an empty text, or neither) by its extension
// (.json in any case: JSON; else XML). `text` may be the file's first bytes only. A text
// decides before a name, so that a string given with the API's default name "scene.xml"
// is read as what it is.
SceneFormat sceneFormatOf(const std::filesystem::path& file, std::string_view text);

// Loads and flattens the scene (XML or JSON, sceneFormatOf). Throws InputError for bad input (SPEC §1), with the file
// and line in the message.
Scene loadScene(const std::filesystem::path& file, const LoadOptions& options = {});

// The same from text in memory (XML or JSON, sceneFormatOf); `file` names it in messages and anchors relative paths.
Scene loadSceneFromText(const std::string& xml, const std::filesystem::path& file,
                        const LoadOptions& options = {});

// The scene document (scene_document.h) of a file, or of XML text: pass 1 only, every
// rule of the parse checked; what flattening checks (masters, cycles, limits, meshes) is
// found by flattenDocument. Throws InputError.
SceneDocument loadSceneDocument(const std::filesystem::path& file, const LoadOptions& options = {});
SceneDocument loadSceneDocumentFromText(const std::string& xml, const std::filesystem::path& file,
                                        const LoadOptions& options = {});

// The document flattened (passes 2 and 3), images and meshes loaded into `resources` on
// first use and copied into the scene. loadScene(file) is flattenDocument(loadSceneDocument
// (file)), bit for bit. Throws InputError (in the document's file's name and lines).
Scene flattenDocument(SceneDocument& document, Resources& resources, const LoadOptions& options = {});

}  // namespace ray
