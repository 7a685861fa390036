// A step of the edit history (edit_session.h) as what the step changed, not as a copy of
// the scene: the parts of a scene document that differ between two of its versions, as
// one of them had them. Applying a patch to the other version gives that one back, and
// yields the patch that goes the other way (undo's patch gives redo's).
//
// The document's small parts (the camera, the globals, the lights, the ids' counters, the
// list of trees) are kept whole; the numbers as typed (SceneDocument::typedNumbers) as the
// entries that differ; a top-level tree that came or went, or whose name or id changed, whole;
// otherwise, of each tree, the run of transblocks (or of one transblock's items, down
// through inline trees) between the first and the last that differ. A colour set on one of
// 20,000 spheres is one sphere's transblock, not 20,000 (issue 49).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene_document.h"

namespace ray::edit {

struct DocumentPatch {
    // The document's parts outside its trees.
    struct Header {
        std::filesystem::path file;
        GlobalCoefficients globals;
        Camera camera;
        std::vector<Light> lights;
        std::vector<std::string> treeOrder;
        int scenefileLine = 0;
        size_t primitiveElements = 0;
        int nextObjectId = 0, nextBlockId = 0, nextNodeId = 0;
        std::vector<int> lightIds;
        std::shared_ptr<const SourceText> source;
        std::vector<SourceId> lightSources;
        std::shared_ptr<const JsonSource> jsonSource;
    };
    // A run of transblocks of a tree (or of items of one transblock) replaced: `count`
    // elements from `at` in the version the patch applies to become `blocks` (`items`).
    struct Splice {
        std::string tree;           // the top-level tree's name
        // From the tree's transblocks down: a transblock's index, then an item's index (an
        // inline tree's), then a transblock's of that tree, ... Even length: the run is of
        // the transblocks of the tree reached; odd: of the items of the transblock reached.
        std::vector<size_t> route;
        size_t at = 0, count = 0;
        std::vector<Block> blocks;
        std::vector<SceneItem> items;
    };
    // A top-level tree taken whole: `tree` is what the name holds in the other version
    // (nullopt: nothing).
    struct TreeSwap {
        std::string name;
        std::optional<NamedTree> tree;
    };

    Header header;
    std::vector<std::pair<std::string, std::optional<std::string>>> numbers;  // typedNumbers' entries (nullopt: none)
    std::vector<TreeSwap> trees;
    std::vector<Splice> splices;

    // About how much memory the patch holds, in bytes (its heap parts counted).
    size_t bytes() const;
};

// What gives `before` back from `after` (after: `before` with an edit made to a copy).
// `settingsOnly`: the edit changed nothing in the trees (the camera, the globals, a light),
// which are then not compared.
DocumentPatch patchBetween(const SceneDocument& before, const SceneDocument& after, bool settingsOnly = false);

// Applies `patch` to `document` (the version it was made against); returns the patch that
// undoes this. Masters are resolved again in `document`.
DocumentPatch applyPatch(SceneDocument& document, DocumentPatch patch);

}  // namespace ray::edit
