// Which parts of two flattened scenes differ: what a renderer that keeps a packed scene from
// frame to frame must pack and upload again after an edit (a material's color, a light, an
// object moved), and what it may keep (the BVH, when no primitive moved).
#pragma once

#include "scene/scene.h"

namespace ray {

struct SceneDifference {
    // The primitives' shapes, transforms, object boxes, motions, meshes and csg objects
    // (with their operands): what the BVH is built from.
    bool geometry = false;
    // Of a geometry difference: only the primitives' (and csg operands') transforms and
    // motions differ, not their number, shapes, meshes or csg programs. A BVH of the same
    // shape then still holds every primitive once its boxes are refitted.
    bool transformsOnly = false;
    bool primitiveMaterials = false;  // which material a primitive uses (geometry unchanged)
    bool materials = false;           // the material table
    bool lights = false;
    bool images = false;              // the textures' pixels
    bool globals = false, camera = false;

    bool any() const { return geometry || primitiveMaterials || materials || lights || images || globals || camera; }
};

// Compares every field that a render reads (not the source file names or lines).
SceneDifference compareScenes(const Scene& a, const Scene& b);

}  // namespace ray
