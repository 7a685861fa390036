// Which parts of two flattened scenes differ, found by comparing them: what a renderer that
// keeps a packed scene from frame to frame must pack and upload again when it has no change
// set for the new scene (scene_changes.h): a file reloaded from disk, a scene it has not
// seen descend from the one it packed.
#pragma once

#include "scene/scene.h"
#include "scene/scene_changes.h"

namespace ray {

using SceneDifference = SceneChanges;

// Compares every field that a render reads (not the source file names or lines, nor the
// lineage).
SceneDifference compareScenes(const Scene& a, const Scene& b);

// What of two scenes renders differently: compareScenes over the images and meshes they use
// alone, each numbered in the order first used. (An editor's scene keeps every image and
// mesh it read, as an image a deleted object used; the same scene loaded from its saved
// file holds those its objects name.) The camera is not compared: renders take their own.
SceneDifference compareRendered(const Scene& a, const Scene& b);

}  // namespace ray
