/// \file
/// A scene for ray's public API: loaded from a CS123 scenefile (a file or a string), or
/// built in code. Coordinates are world space, y up; colors are linear RGB in [0, 1].
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "ray/errors.h"

namespace ray::api {

/// A point, direction or RGB color.
struct Vec3 {
    ///@{
    /// A coordinate, or a color channel (x red, y green, z blue).
    double x = 0, y = 0, z = 0;
    ///@}
};

/// The pinhole (or thin-lens) camera of SPEC §3.
struct Camera {
    Vec3 position{5, 5, 5};           ///< the eye
    Vec3 look{-1, -1, -1};            ///< the viewing direction (need not be unit length)
    Vec3 up{0, 1, 0};                 ///< the direction that is up in the image
    double heightAngleDegrees = 45;   ///< the full vertical field of view
    double aperture = 0;              ///< the lens diameter; 0 is a pinhole
    double focalLength = 0;           ///< the distance in focus (with aperture > 0)
};

/// The kinds of light: the scenefile's point, directional and spot lights, and area lights.
enum class LightType { Point, Directional, Spot, Area };

/// A light of SPEC §4 (names as in `<lightdata>`).
struct Light {
    LightType type = LightType::Point;  ///< which kind; each uses the fields marked for it
    Vec3 color{1, 1, 1};                ///< the light's color (intensity per channel)
    Vec3 attenuation{1, 0, 0};        ///< c1, c2, c3 of 1/(c1 + c2·d + c3·d²)
    Vec3 position{3, 3, 3};           ///< point, spot, area (its centre)
    Vec3 direction{0, 0, -1};         ///< directional, spot, area
    double angleDegrees = 45;         ///< spot: half-angle of the cone
    double penumbraDegrees = 0;       ///< spot: width of the soft band inside the cone
    ///@{
    /// area: the rectangle's width and height.
    double width = 1, height = 1;
    ///@}
};

/// A texture or bump map on a material: a handle from Scene::addTexture*, repeated
/// repeatU × repeatV times over the surface. texture < 0: none.
struct TextureUse {
    /// The handle from Scene::addTextureFromFile or addTextureFromPixels; < 0: none.
    int texture = -1;
    ///@{
    /// How many times the texture repeats over the surface, along u and along v.
    double repeatU = 1, repeatV = 1;
    ///@}
};

/// The material of SPEC §1 (names as in `<object type="primitive">`).
struct Material {
    ///@{
    /// A color of SPEC §1's lighting model, as in the scenefile's `<diffuse>`, `<ambient>`, ...
    Vec3 diffuse{1, 1, 1}, ambient{0, 0, 0}, specular{0, 0, 0};
    Vec3 reflective{0, 0, 0}, transparent{0, 0, 0}, emissive{0, 0, 0};
    ///@}
    double shininess = 0;             ///< the specular exponent
    double ior = 1;                   ///< the index of refraction of a transparent material
    double blend = 0;                 ///< the texture's weight against the diffuse color
    ///@{
    /// The texture (its color, mixed by blend) and the bump map (a height field), if any.
    TextureUse texture, bumpMap;
    ///@}
};

/// The unit shapes of SPEC §2, and a triangle mesh (Scene::addMesh).
enum class Shape { Cube, Sphere, Cylinder, Cone, Torus, Mesh };

/// An affine object-to-world transform: a 3×4 row-major matrix (the last row of the 4×4
/// is 0 0 0 1). Compose with *: (a * b) applies b first, as nested transblocks do.
struct Transform {
    double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};  ///< the matrix's first three rows
    /// A translation by t. Throws InputError when a number is not finite.
    static Transform translate(Vec3 t);
    /// A scale by s.x, s.y, s.z along the axes. Throws InputError when a number is not finite
    /// (a zero scale is refused where the transform is used: it is singular).
    static Transform scale(Vec3 s);
    /// A rotation about axis (through the origin). Throws InputError for a zero axis or a
    /// number that is not finite.
    static Transform rotate(Vec3 axis, double angleDegrees);
};
/// The composition of two transforms: a * b applies b first, then a.
Transform operator*(const Transform& a, const Transform& b);

/// The global coefficients of SPEC §1 (`<globaldata>`).
struct Globals {
    ///@{
    /// The ambient, diffuse, specular and transparent coefficients.
    double ka = 0.5, kd = 0.5, ks = 0.5, kt = 0.5;
    ///@}
};

/// An object of a scene: one `<object type="primitive">` of its scenefile, or one placed
/// with Scene::addPrimitive. An object inside a master is one object however many times
/// the master is placed: editing it (its material, its transform) edits the master, so
/// every instance changes, as editing a component's definition does in a modeler.
struct SceneObject {
    int id = -1;  ///< stable for the scene's life (a removed object's id is never reused)
    /// Its place in the scenefile's tree: "root/transblock[1]/object[0]", or in a master
    /// "leg/transblock[0]/object[0]" (the master's name first); inline trees and csg objects
    /// add their levels ("root/transblock[2]/object[0]/operand[1]/transblock[0]/object[0]").
    std::string path;
    Shape shape = Shape::Cube;  ///< its shape
    /// Its material. A texture is a handle as from addTextureFromFile (a scenefile's
    /// textures have handles too); it is -1 for an object no instance of which is rendered.
    Material material;
    /// Object to world of its first instance (in the order instances are rendered); for an
    /// object with none (in a master no tree places), to its master's frame.
    Transform objectToWorld;
    bool inMaster = false;  ///< in a tree other than "root" (a master)
    size_t instances = 0;   ///< how many instances of it are rendered (masters place it many times)
};

/// A transblock of a scene (`<transblock>`): the transform from its contents to its
/// parent's frame. Editing it moves everything in it, in every instance of its master.
struct SceneNode {
    int id = -1;         ///< stable for the scene's life
    std::string path;    ///< its place in the tree: "root/transblock[1]"
    Transform toParent;  ///< its transforms composed (T1 · T2 · … · Tn)
    std::vector<std::string> masters;  ///< the masters it places (`<object type="master">`), in order
};

// The one edit model. Every edit, from ray view's page, C++ or Python, is one operation on
// the scene's document through one editing service, with one table of editable fields
// (docs/modeler-protocol.md has the model, and its HTTP form). Nodes are named by id
// strings: "camera", "globals", "light-N", "tree-N", "block-N" (a transblock), "object-N",
// "placement-N" (a master placed), "csg-N"; ids are stable for the scene's life. Fields are
// named as the scenefile names them ("diffuse", "shininess", "texture.u").


/// A node's id: "object-12", "light-0", "block-3", "camera", ...
using NodeId = std::string;

/// One step of a transblock, as a scenefile writes it.
struct TransformStep {
    /// translate and scale take x, y, z; rotate an axis x, y, z and an angle in degrees;
    /// matrix the first three rows of a 4×4, row by row (12 numbers).
    enum class Kind { Translate, Rotate, Scale, Matrix };
    Kind kind = Kind::Translate;  ///< which step
    std::vector<double> values;   ///< its numbers, as above
};

/// A field's value. Which alternative a field takes is its FieldInfo::kind: "number" a
/// double, "color" and "vector" a Vec3, "choice", "text" and "file" a string ("" for no
/// file), "matrix" a Transform, "transforms" a list of TransformStep.
using FieldValue = std::variant<double, Vec3, std::string, Transform, std::vector<TransformStep>>;
/// Fields and their values, set together (all or none).
using FieldValues = std::vector<std::pair<std::string, FieldValue>>;

/// One editable field, from the table every editor reads (editableFields()).
struct FieldInfo {
    std::string owner;    ///< the kind of node it belongs to: object, light, camera, globals, transblock, tree
    std::string group;    ///< a heading: material, texture, bump map, transform, light, ...
    std::string name;     ///< the scenefile's name: "diffuse", "texture.u"
    std::string keyword;  ///< the name as a Python keyword: "texture_u"
    std::string kind;     ///< number, color, vector, choice, text, file, transforms, matrix
    std::string help;     ///< one phrase
    ///@{
    /// The range of a number (each of a color's or vector's): -inf, +inf when open.
    double min = 0, max = 0;
    bool minIncluded = true, maxIncluded = true;
    ///@}
    std::vector<std::string> lights;  ///< a light's field: the light types using it (empty: all)
    std::vector<std::string> choices; ///< a choice's choices
};

/// Every editable field, in the order an editor shows them.
std::vector<FieldInfo> editableFields();

/// What an edit did.
struct EditResult {
    /// What the renderer re-packs for it: geometry (a rebuild) or transforms (a refit),
    /// primitives, materials, lights, textures, globals, camera.
    std::vector<std::string> changed;
    std::vector<NodeId> added;    ///< nodes made: the object (then its transblock), the copies, ...
    std::vector<NodeId> removed;  ///< nodes removed
};

/// One node of the scene's tree (Scene::outline()).
struct OutlineEntry {
    NodeId node;          ///< its id
    NodeId parent;        ///< its parent's id; "" for the camera, globals, lights and trees
    int depth = 0;        ///< how deep it is in the tree
    std::string kind;     ///< camera, globals, light, tree, transblock, object, placement, csg
    /// The kind in the words of the scene's file format, as ray view's outline shows it: an XML
    /// scene's is `kind`; a JSON scene's (SPEC §7) "groups" (the tree "root"), "template group"
    /// (another tree), "group" (a transblock), "template use" (a placement), else `kind`.
    std::string label;
    std::string text;     ///< what it is: "sphere", "point light", "master leg" (JSON: the template's name)
    /// Its place in the file: "root/transblock[1]/object[0]"; a JSON scene's as its reader names
    /// it, "groups[1].primitives[0]", "groups[0].lights[0]"; "" for the camera, the globals, an
    /// XML scene's lights and a JSON light added since the file was read.
    std::string path;
};

class Scene;

/// How a scenefile is read.
struct LoadOptions {
    std::vector<std::filesystem::path> searchPaths;  ///< extra roots for textures and meshes
    bool strict = false;                             ///< every warning becomes an InputError
    bool loadTextures = true;                        ///< false: skip reading image files
};

/// The most pixels a texture may have, from a file or from memory (8192 × 4096).
constexpr uint64_t kMaxTexturePixels = uint64_t(1) << 25;

/// How Scene::save and saveImage treat what is at the file they write. A regular file is
/// replaced whole, keeping its mode; a symbolic link is written through to its target; a
/// character device or FIFO is written into; a folder, block device or socket is refused
/// (InputError), and so is a read-only file unless replaceReadOnly says to replace it.
struct WriteOptions {
    bool replaceReadOnly = false;   ///< replace a read-only file (refused otherwise)
    bool overwriteChanges = false;  ///< Scene::save: replace a file another program changed since (refused otherwise)
};

struct LoadResult;

/// A scene: what a Renderer renders. Copyable (a copy is independent) and movable.
class Scene {
public:
    Scene();  ///< empty: the default camera, no lights, no primitives
    ~Scene();
    Scene(const Scene&);  ///< an independent copy
    Scene& operator=(const Scene&);  ///< makes this an independent copy
    Scene(Scene&&) noexcept;  ///< takes the other's contents
    Scene& operator=(Scene&&) noexcept;  ///< takes the other's contents

    /// Reads a scenefile, CS123's XML or CS1230's JSON (by the file's first character, else
    /// its extension). Throws InputError ("file:line: error: ...").
    static LoadResult load(const std::filesystem::path& file, const LoadOptions& options = {});
    /// Reads a scenefile's XML or JSON from a string (JSON when it starts with '{'); `name`
    /// stands for the file in messages and is the folder relative texture and mesh paths are
    /// found from.
    static LoadResult fromString(const std::string& xml, const std::filesystem::path& name = "scene.xml",
                                 const LoadOptions& options = {});

    Camera camera() const;  ///< the camera
    /// Replaces the camera. Throws InputError for a camera the scenefile loader would refuse.
    void setCamera(const Camera& camera);
    Globals globals() const;  ///< the global coefficients
    /// Replaces the global coefficients. Throws InputError for values the loader would refuse.
    void setGlobals(const Globals& globals);

    /// Adds a light. Throws InputError for values the scenefile loader would refuse.
    void addLight(const Light& light);
    /// Returns the material's handle, for addPrimitive.
    int addMaterial(const Material& material);
    /// A texture from an image file (png, jpg, ...). Throws InputError when unreadable.
    int addTextureFromFile(const std::filesystem::path& file);
    /// A texture from memory: width × height RGB triples in [0, 1], row 0 at the top.
    int addTextureFromPixels(int width, int height, const std::vector<float>& rgb);
    /// A triangle mesh: positions (x, y, z per vertex), triangles (three vertex indices
    /// each, counter-clockwise from the front), and optionally one normal and one (u, v)
    /// per vertex (empty: face normals, (0, 0)). Throws InputError for bad indices.
    int addMesh(const std::vector<float>& positions, const std::vector<uint32_t>& triangles,
                const std::vector<float>& normals = {}, const std::vector<float>& uvs = {});
    /// Places a primitive (the unit shapes of SPEC §2; Shape::Mesh needs `mesh` from addMesh).
    /// Returns the new object's id (Scene::objects): it is in a transblock of its own at the
    /// end of the root tree.
    int addPrimitive(Shape shape, const Transform& objectToWorld, int material, int mesh = -1);
    /// Places a primitive inside transblock `nodeId` (from nodes()), in a transblock of its
    /// own whose transform is `toNode` (object to the node's frame): inside a master it is
    /// in every instance. Returns its id. Throws InputError for a node that does not exist,
    /// a singular transform, or handles that do not exist.
    int addPrimitiveTo(int nodeId, Shape shape, const Transform& toNode, int material, int mesh = -1);

    size_t primitiveCount() const;  ///< the primitives placed (a scenefile's, flattened, and added ones)
    size_t lightCount() const;  ///< the lights

    /// \name The scene as its file has it: read it, edit it, save it
    /// The scene keeps its scenefile's tree (transblocks, objects, masters), not only the
    /// primitives it flattens to; every edit re-flattens it, so the next render shows it.
    /// An edit that fails throws InputError and changes nothing.
    ///@{

    /// Every object, in the scenefile's order (masters in the order the file lists them,
    /// objects added in code last).
    std::vector<SceneObject> objects() const;
    /// The object with this id. Throws InputError when there is none (removed, say).
    SceneObject object(int id) const;
    /// The object the rendered primitive `instance` (0 .. primitiveCount() - 1, as a
    /// Renderer's pick reports it) is an instance of. Throws InputError out of range.
    int objectOfInstance(size_t instance) const;
    /// Replaces the object's material (in every instance). Throws InputError for values the
    /// scenefile loader would refuse (a negative shininess, say), a texture handle that
    /// does not exist, or an object that does not.
    void setMaterial(int id, const Material& material);
    /// Places the object so that its first instance's object-to-world transform is
    /// `objectToWorld` (its other instances, through masters, keep their place relative to
    /// it). Its transblock takes the transform if the object is alone in it; otherwise the
    /// object gets a transblock of its own. Throws InputError for a singular transform.
    void setObjectToWorld(int id, const Transform& objectToWorld);
    /// Removes the object (from its master: from every instance). Throws InputError for an
    /// object that does not exist, or whose removal would leave a csg operand empty.
    void removeObject(int id);

    /// Every transblock, in the scenefile's order.
    std::vector<SceneNode> nodes() const;
    /// Replaces the transblock's transforms with `toParent`. Throws InputError for a
    /// singular transform or a transblock that does not exist.
    void setNodeTransform(int nodeId, const Transform& toParent);

    /// The lights, in order (index i is the scenefile's i-th `<lightdata>`).
    std::vector<Light> lights() const;
    /// Replaces light `index`. Throws InputError for an index out of range or values the
    /// loader would refuse.
    void setLight(size_t index, const Light& light);
    /// Removes light `index` (the later ones move down). Throws InputError out of range.
    void removeLight(size_t index);

    /// The scene as CS123 scenefile text, which loads back to the same scene (masters as
    /// masters, transforms as written). A scene loaded from a file is that file's text with
    /// what was edited changed (unedited, the file byte for byte); one built in code is
    /// written afresh. Paths the scene changed are relative to the folder of the file it
    /// was loaded from (the current folder for a scene built in code). Throws InputError
    /// for what a scenefile cannot hold: a texture or mesh made in memory.
    std::string toText() const;
    /// Writes toText() to `file` atomically (all of it, or the old file is left as it was),
    /// with texture and mesh paths as the scene's file writes them when `file` is in its
    /// folder, relative to `file`'s folder otherwise. Loading it renders the same
    /// image, byte for byte. A `file` named .json gets the course's JSON (CS1230, 2023 on:
    /// masters as templates, lights as groups placing them; paths relative to the folder
    /// above `file`'s), a scene loaded from XML converted as `ray convert` converts it;
    /// what JSON cannot hold (a torus, an area light, an emissive colour) throws InputError
    /// with the reason. Throws InputError as toText() does, DeviceError when the file
    /// cannot be written.
    ///
    /// A file this scene was loaded from or saved to is not replaced when another program
    /// changed it since (its size or bytes differ from what this scene read or wrote):
    /// InputError says so, and nothing is written, so that their change is not lost.
    /// WriteOptions::overwriteChanges replaces it all the same.
    void save(const std::filesystem::path& file) const;
    /// save(), with how a read-only file and a file changed since are treated (WriteOptions).
    void save(const std::filesystem::path& file, const WriteOptions& options) const;
    ///@}

    /// \name The one edit model (docs/modeler-protocol.md)
    /// The operations ray view's page makes, by node id and field name: each checked whole
    /// (InputError naming the field, and nothing changes), each saying what it changed.
    /// The typed functions above are these for their structs.
    ///@{

    /// Every node, in document order (the camera, the globals, the lights, then the trees).
    std::vector<OutlineEntry> outline() const;
    /// Field `field` of `node`. Throws InputError for a node or field that does not exist.
    FieldValue field(const NodeId& node, const std::string& field) const;
    /// Sets fields of one node: a material and texture of an object, its "transform" (its
    /// own transblock's steps) or "world" (where it is: it moves alone, getting a transblock
    /// of its own if it shares one), a light, the camera, the globals, a transblock's
    /// "transform", a tree's "name".
    EditResult set(const NodeId& node, const FieldValues& fields);
    /// A primitive ("cube", "cylinder", "cone", "sphere", "torus", or "mesh" with `meshFile`,
    /// an .obj) in a transblock of its own, at the end of the root tree or inside transblock
    /// `parent`, with `fields` set (its material, "transform", "world"). added: the object,
    /// then its transblock.
    EditResult add(const std::string& shape, const FieldValues& fields = {}, const NodeId& parent = "",
                   const std::filesystem::path& meshFile = {});
    /// A light of `type` (point, directional, spot, area) with `fields` set.
    EditResult addLight(const std::string& type, const FieldValues& fields = {});
    /// Removes objects, lights, transblocks (with what they hold), placements, csg objects.
    EditResult remove(const std::vector<NodeId>& nodes);
    /// A copy of each node right after it.
    EditResult duplicate(const std::vector<NodeId>& nodes);
    /// Objects of one transblock moved into a new transblock there.
    EditResult group(const std::vector<NodeId>& nodes);
    /// Renames a tree (a master) and every placement of it.
    EditResult rename(const NodeId& tree, const std::string& name);
    /// Gives a placement of a master a copy of the master of its own: editing it then
    /// changes that placement alone.
    EditResult makeUnique(const NodeId& placement);
    ///@}

    /// \cond INTERNAL
    struct Impl;
    const Impl& impl() const { return *impl_; }
    /// \endcond

private:
    std::unique_ptr<Impl> impl_;
};

/// A scene read from a scenefile, and the warnings reading it gave.
struct LoadResult {
    Scene scene;                        ///< the scene
    std::vector<std::string> warnings;  ///< complete ("scene.xml:7: warning: ..."), in order
};

}  // namespace ray::api
