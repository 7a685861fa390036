// The flattened scene: the one input both renderers take.
//
// The loader (scene_loader.h) turns a scenefile's tree of transblocks and masters into a
// flat list of primitive instances, each with its object-to-world transform and inverse
// and an index into a table of materials. Materials are shared: every instance that comes
// from the same <object type="primitive"> element (through masters, say) shares one.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "image/image.h"
#include "core/math.h"
#include "scene/csg.h"
#include "scene/mesh.h"
#include "scene/scene_changes.h"

namespace ray {

// Global lighting coefficients (SPEC §1, <globaldata>). The course's defaults are 0.5.
struct GlobalCoefficients {
    double ka = 0.5;  // ambient
    double kd = 0.5;  // diffuse
    double ks = 0.5;  // specular, and the reflection weight k_r
    double kt = 0.5;  // transparency
};

struct Camera {
    Vec3 position{5, 5, 5};
    Vec3 look{-1, -1, -1};  // a direction, not normalized
    Vec3 up{0, 1, 0};
    double heightAngleDegrees = 45;  // full vertical field of view
    double aperture = 0;             // diameter of the lens disk; 0 is a pinhole
    double focalLength = 0;          // distance to the plane in focus; 0 = unset

    bool operator==(const Camera&) const = default;
};

enum class LightType { Point, Directional, Spot, Area };
// The scenefile's name of the type (<type v="..."/> in <lightdata>).
const char* lightTypeName(LightType type);

struct Light {
    LightType type = LightType::Point;
    Vec3 color{1, 1, 1};
    Vec3 attenuation{1, 0, 0};  // c1, c2, c3 of f_att = 1/(c1 + c2·d + c3·d²)
    Vec3 position{3, 3, 3};
    Vec3 direction{0, 0, -1};  // directional, spot and area lights
    double angleDegrees = 45;     // spot: outer half-angle of the cone
    double penumbraDegrees = 0;   // spot: width of the falloff band inside the cone
    double radius = 0;            // spot: read and kept, not used by the lighting model
    double width = 1, height = 1; // area: the rectangle's size
};

// A texture or bump map reference: an index into Scene::images (-1: none, or the file
// was missing) and the repeat counts.
struct TextureMap {
    int image = -1;
    double repeatU = 1, repeatV = 1;
};

struct Material {
    Vec3 diffuse{1, 1, 1};
    Vec3 ambient{0, 0, 0};
    Vec3 specular{0, 0, 0};
    Vec3 reflective{0, 0, 0};
    Vec3 transparent{0, 0, 0};
    Vec3 emissive{0, 0, 0};
    double shininess = 0;
    double ior = 1;
    double blend = 0;  // weight of the texture color against kd·Od
    TextureMap texture;
    TextureMap bumpMap;
};

// The values of these are part of the packed device layout too (cl/shared_types.h).
enum class PrimitiveType : int { Cube = 0, Sphere = 1, Cylinder = 2, Cone = 3, Torus = 4, Mesh = 5, Csg = 6 };

const char* primitiveTypeName(PrimitiveType type);

struct PrimitiveInstance {
    Affine objectToWorld;
    Affine worldToObject;
    PrimitiveType type = PrimitiveType::Cube;
    int material = 0;
    int mesh = -1;  // index into Scene::meshFiles (and Scene::meshes) for PrimitiveType::Mesh
    int csg = -1;   // index into Scene::csgObjects for PrimitiveType::Csg (scene/csg.h)
    // The object-space box holding the primitive: the unit cube [−0.5, 0.5]³ by default, the
    // torus's own slimmer box, a mesh's bounds. Both BVHs box instances with it.
    Vec3 objectLo{-0.5, -0.5, -0.5}, objectHi{0.5, 0.5, 0.5};
    // Motion blur (the <motion> extension, scene_loader.cpp): the world-space displacement
    // reached at the end of the shutter. At shutter time t ∈ [0, 1] the instance is
    // translated by t·motion (objectToWorld is its place at t = 0); zero: it stands still.
    Vec3 motion{0, 0, 0};
    // The line of the <object type="primitive"> element in Scene::sourceFile this instance
    // comes from (0: not from a file), for messages and `ray explain`.
    int sourceLine = 0;
    // The stable id of the document object (the <object type="primitive"> element, or the
    // object made in code, scene/scene_document.h) this instance comes from; -1: none. A
    // csg instance names its first operand's object, whose material it is shaded with.
    int sourceObject = -1;
};

// Sets the instance's object-space box for its type (the unit cube, the torus's box, its
// mesh's bounds: instance.mesh indexes meshes).
void fitObjectBox(PrimitiveInstance& instance, const std::vector<TriangleMesh>& meshes);

struct Scene {
    std::filesystem::path sourceFile;
    GlobalCoefficients globals;
    Camera camera;
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<PrimitiveInstance> primitives;
    // Textures and bump maps, each file loaded once however many materials name it.
    std::vector<Image> images;
    std::vector<std::filesystem::path> imageFiles;
    // Resolved OBJ files named by mesh primitives, and their triangles (meshes[i] read
    // from meshFiles[i]), each stored once however many instances use it.
    std::vector<std::filesystem::path> meshFiles;
    std::vector<TriangleMesh> meshes;
    // Constructive solid geometry (scene/csg.h): each PrimitiveType::Csg instance names one
    // object here, whose program combines operand instances kept in csgOperands (never in
    // primitives: they are only ever intersected through their csg object).
    std::vector<CsgObject> csgObjects;
    std::vector<PrimitiveInstance> csgOperands;
    // Which scene this is, and what the edits that made it from earlier ones changed
    // (scene_changes.h): a renderer that packed an earlier one re-packs that alone.
    SceneLineage lineage;
};

// Bad input: the message is complete ("scene.xml:12: error: ..."), ready to print.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace ray
