// What changed in a flattened scene, at the grain the renderers keep it in (a change set):
// said by the edit that made the change (edit/edit_session.h), so that a renderer that
// keeps a packed scene from frame to frame re-packs and re-uploads that alone, with no
// comparison of the scenes. Comparing two scenes (scene_difference.h) is left for a scene
// with no such history: a file reloaded from disk.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ray {

struct SceneChanges {
    // The primitives' shapes, transforms, object boxes, motions, meshes and csg objects
    // (with their operands): what the BVH is built from.
    bool geometry = false;
    // Of a geometry change: only the primitives' (and csg operands') transforms and
    // motions changed, not their number, order, shapes, meshes or csg programs. A BVH of
    // the same shape then still holds every primitive once its boxes are refitted.
    bool transformsOnly = false;
    bool primitiveMaterials = false;  // which material a primitive uses (geometry unchanged)
    bool materials = false;           // the material table
    bool lights = false;
    bool images = false;              // the textures' pixels
    bool globals = false, camera = false;

    bool any() const { return geometry || primitiveMaterials || materials || lights || images || globals || camera; }
    // Both changes, one after the other: a refit stays a refit only when both are.
    SceneChanges& operator|=(const SceneChanges& other);
    // Whether every change `other` says is said here too (a refit is within a rebuild).
    bool covers(const SceneChanges& other) const;
    // The parts, as the viewer's protocol names them: "geometry" (a rebuild) or
    // "transforms" (a refit), "primitives", "materials", "lights", "textures", "globals",
    // "camera".
    std::vector<std::string> names() const;

    bool operator==(const SceneChanges&) const = default;
};

// A flattened scene's place among the scenes its edits made: its revision (unique in the
// process), and the change sets of the edits that led to it from the revisions before it,
// the latest last. A scene loaded from a file has a fresh revision and no edits. A change
// of the scene's own camera alone keeps the revision: renderers take each frame's camera
// from their caller, so such a scene renders as the one before it (an API caller orbiting
// the camera frame after frame makes no new revisions, and no renderer re-packs).
struct SceneLineage {
    struct Step {
        uint64_t from = 0;  // the revision the edit was made to
        SceneChanges changes;
    };
    uint64_t revision = 0;
    std::vector<Step> steps;  // at most kMaxSteps

    // How many edits back a renderer may be and still be told what changed (beyond, it
    // compares the scenes): a drag's requests outrun frames by a few, not by 32.
    static constexpr size_t kMaxSteps = 32;

    // A revision no scene had before.
    static uint64_t fresh();
    // The lineage of a scene made from the one of `before` by an edit that changed `changes`.
    static SceneLineage after(const SceneLineage& before, const SceneChanges& changes);
    // What changed since the scene of `revision`: every step after it, together; nullopt
    // when this scene does not descend from it within kMaxSteps (a reload, another scene).
    std::optional<SceneChanges> changesSince(uint64_t revision) const;
};

}  // namespace ray
