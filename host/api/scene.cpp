// The public Scene (include/ray/scene.h): the editing service (edit/edit_session.h) over a
// scene document, as ray view's page edits it. Every edit is one operation of the one edit
// model: the typed functions (setMaterial, setLight, setCamera, ...) turn their structs into
// the field table's inputs (edit/struct_fields.h) and apply them; the generic ones (set,
// add, remove, ...) take node ids and field names. Each is checked whole (InputError, and
// nothing changes) and says what it changed, which the flattened scene carries to the
// Renderer's frame source (it re-packs that alone). Adding primitives at the end of the
// root tree changes the scene in place: scenes built in code add them by the thousand.
#include "ray/scene.h"

#include <cmath>
#include <map>

#include "api/camera_conversion.h"
#include "api/edit_conversion.h"
#include "api/error_translation.h"
#include "api/input_checks.h"
#include "scene/document_save.h"
#include "api/scene_impl.h"
#include "core/math.h"
#include "core/message_text.h"
#include "edit/edit_error.h"
#include "edit/field_values.h"
#include "edit/struct_fields.h"
#include "image/image.h"
#include "scene/file_search.h"
#include "scene/scene_loader.h"

namespace ray::api {

namespace {

using detail::toInternal;
using detail::toPublic;
namespace edit = ray::edit;

ray::TextureMap internal(const TextureUse& use) { return {use.texture, use.repeatU, use.repeatV}; }

ray::Material internal(const Material& material) {
    ray::Material m;
    m.diffuse = toInternal(material.diffuse);
    m.ambient = toInternal(material.ambient);
    m.specular = toInternal(material.specular);
    m.reflective = toInternal(material.reflective);
    m.transparent = toInternal(material.transparent);
    m.emissive = toInternal(material.emissive);
    m.shininess = material.shininess;
    m.ior = material.ior;
    m.blend = material.blend;
    m.texture = internal(material.texture);
    m.bumpMap = internal(material.bumpMap);
    return m;
}

Material external(const ray::Material& m) {
    Material material;
    material.diffuse = toPublic(m.diffuse);
    material.ambient = toPublic(m.ambient);
    material.specular = toPublic(m.specular);
    material.reflective = toPublic(m.reflective);
    material.transparent = toPublic(m.transparent);
    material.emissive = toPublic(m.emissive);
    material.shininess = m.shininess;
    material.ior = m.ior;
    material.blend = m.blend;
    material.texture = {m.texture.image, m.texture.repeatU, m.texture.repeatV};
    material.bumpMap = {m.bumpMap.image, m.bumpMap.repeatU, m.bumpMap.repeatV};
    return material;
}

ray::Light internal(const Light& light) {
    ray::Light l;
    l.type = ray::LightType(int(light.type));  // same order: Point, Directional, Spot, Area
    l.color = toInternal(light.color);
    l.attenuation = toInternal(light.attenuation);
    l.position = toInternal(light.position);
    l.direction = toInternal(light.direction);
    l.angleDegrees = light.angleDegrees;
    l.penumbraDegrees = light.penumbraDegrees;
    l.width = light.width;
    l.height = light.height;
    return l;
}

Light external(const ray::Light& l) {
    Light light;
    light.type = LightType(int(l.type));
    light.color = toPublic(l.color);
    light.attenuation = toPublic(l.attenuation);
    light.position = toPublic(l.position);
    light.direction = toPublic(l.direction);
    light.angleDegrees = l.angleDegrees;
    light.penumbraDegrees = l.penumbraDegrees;
    light.width = l.width;
    light.height = l.height;
    return light;
}

ray::LoadOptions internal(const LoadOptions& options, std::vector<std::string>& warnings) {
    ray::LoadOptions load;
    load.searchPaths = options.searchPaths;
    for (auto& path : searchPathsFromEnvironment()) load.searchPaths.push_back(path);
    load.strict = options.strict;
    load.loadImages = options.loadTextures;
    load.warn = [&warnings](const std::string& message) { warnings.push_back(message); };
    return load;
}

[[noreturn]] void badInput(const std::string& what) { throw InputError("error: " + what, "", 0); }

void checkIndex(int index, size_t count, const char* what) {
    if (index < 0 || size_t(index) >= count)
        badInput(std::string(what) + " " + std::to_string(index) + " does not exist (the scene has " +
                 std::to_string(count) + "); use a handle returned by its add function");
}

void checkIndex(size_t index, size_t count, const char* what) {
    checkIndex(int(std::min<size_t>(index, size_t(INT32_MAX))), count, what);
}

edit::NodeId objectNode(int id) { return {edit::NodeKind::Object, id}; }

// Applies one operation of the edit model; its errors as the public InputError.
edit::Outcome apply(Scene::Impl& impl, const edit::Operation& operation) {
    return detail::translatingErrors([&] { return impl.session.apply(operation); });
}

// The document to walk: walking does not change it (its walks take a document they may
// hand out places of).
ray::SceneDocument& walkable(const Scene::Impl& impl) { return const_cast<ray::SceneDocument&>(impl.document()); }

// A transform of one step, a matrix: what the API's Transforms are.
edit::FieldInput matrixTransform(const char* field, edit::FieldOwner owner, const Transform& t) {
    return {edit::findField(owner, field), std::vector<ray::TransformOp>{ray::TransformOp::matrix(toInternal(t))}, {}};
}

[[noreturn]] void noObject(int id) {
    badInput("object " + std::to_string(id) + " does not exist (removed, or never made); take ids from Scene::objects()");
}

SceneObject describe(const ray::Scene& scene, const ray::PrimitiveNode& node, const ray::DocumentPlace& place,
                     const std::map<int, std::pair<const ray::PrimitiveInstance*, size_t>>& instances) {
    SceneObject object;
    object.id = node.id;
    object.path = place.path;
    object.shape = Shape(int(node.type));  // same order as PrimitiveType (a primitive is never a csg)
    object.inMaster = place.tree->name != "root";
    auto found = instances.find(node.id);
    const ray::PrimitiveInstance* first = found == instances.end() ? nullptr : found->second.first;
    object.instances = found == instances.end() ? 0 : found->second.second;
    object.material = external(first ? scene.materials[size_t(first->material)] : node.material);
    object.objectToWorld = toPublic(first ? first->objectToWorld : ray::composedPlacement(place.blocks).first);
    return object;
}

// Each object's first instance and how many it has (only object `only`, when >= 0).
std::map<int, std::pair<const ray::PrimitiveInstance*, size_t>> instancesOf(const ray::Scene& scene, int only = -1) {
    std::map<int, std::pair<const ray::PrimitiveInstance*, size_t>> byObject;
    for (const auto* list : {&scene.primitives, &scene.csgOperands})
        for (const ray::PrimitiveInstance& instance : *list) {
            if (instance.type == ray::PrimitiveType::Csg) continue;  // its operands count
            if (instance.sourceObject < 0 || (only >= 0 && instance.sourceObject != only)) continue;
            auto& entry = byObject[instance.sourceObject];
            if (!entry.first) entry.first = &instance;
            ++entry.second;
        }
    return byObject;
}

// Every number of a light struct, those its type does not use too: a Light holds no number
// a scenefile could not.
void checkEveryField(const ray::Light& light) {
    detail::translatingErrors([&] {
        for (const edit::FieldInput& input : edit::lightFields(light, true)) edit::checkFieldValue(input, "light");
    });
}

edit::NodeId lightNode(const Scene::Impl& impl, size_t index) {
    checkIndex(index, impl.document().lights.size(), "light");
    return {edit::NodeKind::Light, impl.document().lightIds[index]};
}

// The key of a file in Scene::Impl::files.
std::filesystem::path fileKey(const std::filesystem::path& file) {
    std::error_code ec;
    std::filesystem::path key = std::filesystem::weakly_canonical(file, ec);
    return ec ? std::filesystem::absolute(file).lexically_normal() : key;
}

// Loads the document with `read` into a fresh session.
template <class Read>
void loadInto(std::unique_ptr<Scene::Impl>& impl, const LoadOptions& options, std::vector<std::string>& warnings,
              Read read) {
    detail::translatingErrors([&] {
        ray::LoadOptions load = internal(options, warnings);
        ray::SceneDocument document = read(load);
        auto loaded = std::make_unique<Scene::Impl>(std::move(document), load);  // flattening warns here too
        impl = std::move(loaded);
    });
}

}  // namespace

std::vector<FieldInfo> editableFields() {
    std::vector<FieldInfo> fields;
    for (const edit::EditField& field : edit::editFields()) fields.push_back(toPublic(field));
    return fields;
}

Transform Transform::translate(Vec3 t) {
    detail::checkFinite("translate", t);
    return toPublic(ray::Affine::translation(toInternal(t)));
}
Transform Transform::scale(Vec3 s) {
    detail::checkFinite("scale", s);
    return toPublic(ray::Affine::scaling(toInternal(s)));
}
Transform Transform::rotate(Vec3 axis, double angleDegrees) {
    detail::checkFinite("rotate's axis", axis);
    detail::checkFinite("rotate's angle", angleDegrees);
    if (axis.x == 0 && axis.y == 0 && axis.z == 0)
        badInput("rotate: the axis (0, 0, 0) has no direction; give a non-zero axis, such as (0, 1, 0)");
    return toPublic(ray::Affine::rotation(toInternal(axis), angleDegrees));
}
Transform operator*(const Transform& a, const Transform& b) { return toPublic(toInternal(a) * toInternal(b)); }

Scene::Scene() : impl_(std::make_unique<Impl>()) {}
Scene::~Scene() = default;
Scene::Scene(const Scene& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
Scene& Scene::operator=(const Scene& other) {
    if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
    return *this;
}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

LoadResult Scene::load(const std::filesystem::path& file, const LoadOptions& options) {
    LoadResult result;
    // Stamped before it is read: a change made while it is read is one a save asks about.
    const edit::FileStamp stamp = edit::stampOf(file);
    loadInto(result.scene.impl_, options, result.warnings,
             [&](const ray::LoadOptions& load) { return ray::loadSceneDocument(file, load); });
    result.scene.impl_->files[fileKey(file)] = stamp;
    return result;
}

LoadResult Scene::fromString(const std::string& xml, const std::filesystem::path& name, const LoadOptions& options) {
    LoadResult result;
    loadInto(result.scene.impl_, options, result.warnings,
             [&](const ray::LoadOptions& load) { return ray::loadSceneDocumentFromText(xml, name, load); });
    return result;
}

Camera Scene::camera() const { return toPublic(impl_->document().camera); }

void Scene::setCamera(const Camera& camera) {
    apply(*impl_, edit::SetFields{{edit::NodeKind::Camera, 0}, edit::cameraFields(toInternal(camera))});
}

Globals Scene::globals() const {
    const ray::GlobalCoefficients& g = impl_->document().globals;
    return {g.ka, g.kd, g.ks, g.kt};
}

void Scene::setGlobals(const Globals& globals) {
    apply(*impl_, edit::SetFields{{edit::NodeKind::Globals, 0},
                                  edit::globalsFields({globals.ka, globals.kd, globals.ks, globals.kt})});
}

void Scene::addLight(const Light& light) {
    checkEveryField(internal(light));
    std::vector<edit::FieldInput> fields = edit::lightFields(internal(light));
    fields.erase(fields.begin());  // its type: the operation's
    apply(*impl_, edit::AddLight{ray::LightType(int(light.type)), std::move(fields)});
}

int Scene::addMaterial(const Material& material) {
    const ray::Material m = internal(material);
    detail::translatingErrors([&] {
        for (const edit::FieldInput& input : edit::materialFields(m, false)) edit::checkFieldValue(input, "material");
    });
    const size_t images = impl_->session.resources().images.size();
    if (material.texture.texture >= 0) checkIndex(material.texture.texture, images, "texture");
    if (material.bumpMap.texture >= 0) checkIndex(material.bumpMap.texture, images, "bump map texture");
    impl_->materials.push_back(m);
    return int(impl_->materials.size() - 1);
}

int Scene::addTextureFromFile(const std::filesystem::path& file) {
    ray::Image image;
    try {
        image = ray::readImage(file);
    } catch (const ray::ImageError& e) {
        throw InputError(e.what(), file.string(), 0);
    }
    return impl_->session.addImage(std::move(image));
}

int Scene::addTextureFromPixels(int width, int height, const std::vector<float>& rgb) {
    detail::checkTextureSize(width, height);
    if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3)
        badInput("a texture of " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                 "width*height*3 floats, not " + std::to_string(rgb.size()));
    ray::Image image(width, height);
    image.rgb = rgb;
    return impl_->session.addImage(std::move(image));
}

int Scene::addMesh(const std::vector<float>& positions, const std::vector<uint32_t>& triangles,
                   const std::vector<float>& normals, const std::vector<float>& uvs) {
    const size_t vertices = positions.size() / 3;
    if (positions.size() % 3 != 0 || triangles.empty() || triangles.size() % 3 != 0)
        badInput("a mesh needs x, y, z per vertex and three vertex indices per triangle");
    if ((!normals.empty() && normals.size() != positions.size()) || (!uvs.empty() && uvs.size() != vertices * 2))
        badInput("a mesh's normals (3 floats) and uvs (2 floats) come one per vertex, or not at all");
    ray::TriangleMesh mesh;
    for (size_t v = 0; v < vertices; ++v) {
        mesh.positions.push_back({positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]});
        if (!normals.empty()) mesh.normals.push_back({normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]});
        if (!uvs.empty()) mesh.texCoords.push_back({uvs[2 * v], uvs[2 * v + 1]});
    }
    for (size_t t = 0; t < triangles.size(); t += 3) {
        std::array<ray::MeshCorner, 3> corners;
        for (int k = 0; k < 3; ++k) {
            const uint32_t index = triangles[t + size_t(k)];
            if (index >= vertices)
                badInput("mesh triangle " + std::to_string(t / 3) + " names vertex " + std::to_string(index) +
                         " of " + std::to_string(vertices));
            corners[size_t(k)] = {int(index), normals.empty() ? -1 : int(index), uvs.empty() ? -1 : int(index)};
        }
        mesh.triangles.push_back(corners);
    }
    mesh.computeBounds();
    return impl_->session.addMesh(std::move(mesh));
}

namespace {

// A primitive of `shape` with material handle `material`, placed by `transform` (object to
// world, or to the transblock it is added to).
edit::AddPrimitive primitiveToAdd(const Scene::Impl& impl, Shape shape, const Transform& transform, int material,
                                  int mesh) {
    checkIndex(material, impl.materials.size(), "material");
    if (shape == Shape::Mesh) checkIndex(mesh, impl.session.resources().meshes.size(), "mesh");
    edit::AddPrimitive add;
    add.shape = ray::PrimitiveType(int(shape));  // same order as PrimitiveType
    add.mesh = shape == Shape::Mesh ? mesh : -1;
    add.fields = edit::materialFields(impl.materials[size_t(material)], true);
    add.fields.push_back(matrixTransform("transform", edit::FieldOwner::Object, transform));
    return add;
}

}  // namespace

int Scene::addPrimitive(Shape shape, const Transform& objectToWorld, int material, int mesh) {
    return apply(*impl_, primitiveToAdd(*impl_, shape, objectToWorld, material, mesh)).added.front().number;
}

int Scene::addPrimitiveTo(int nodeId, Shape shape, const Transform& toNode, int material, int mesh) {
    edit::AddPrimitive add = primitiveToAdd(*impl_, shape, toNode, material, mesh);
    add.parent = edit::NodeId{edit::NodeKind::Block, nodeId};
    return apply(*impl_, add).added.front().number;
}

size_t Scene::primitiveCount() const { return impl_->flattened()->primitives.size(); }
size_t Scene::lightCount() const { return impl_->document().lights.size(); }

std::vector<SceneObject> Scene::objects() const {
    const std::shared_ptr<const ray::Scene> scene = impl_->flattened();
    const auto instances = instancesOf(*scene);
    std::vector<SceneObject> objects;
    ray::forEachObject(walkable(*impl_), [&](ray::PrimitiveNode& node, const ray::DocumentPlace& place) {
        objects.push_back(describe(*scene, node, place, instances));
    });
    return objects;
}

SceneObject Scene::object(int id) const {
    std::optional<ray::DocumentPlace> place = ray::findObject(walkable(*impl_), id);
    if (!place) noObject(id);
    const std::shared_ptr<const ray::Scene> scene = impl_->flattened();
    return describe(*scene, std::get<ray::PrimitiveNode>(place->block->items[place->item]), *place,
                    instancesOf(*scene, id));
}

int Scene::objectOfInstance(size_t instance) const {
    const std::vector<ray::PrimitiveInstance>& primitives = impl_->flattened()->primitives;
    if (instance >= primitives.size())
        badInput("instance " + std::to_string(instance) + " does not exist (the scene renders " +
                 std::to_string(primitives.size()) + ")");
    return primitives[instance].sourceObject;
}

void Scene::setMaterial(int id, const Material& material) {
    const SceneObject current = object(id);
    std::vector<edit::FieldInput> fields = edit::materialFields(internal(material), true);
    // A texture the file names stays named by it (so a saved file names it as it did)
    // unless another one replaces it: then the handle's own file is written.
    std::erase_if(fields, [&](const edit::FieldInput& input) {
        const edit::SpecialField special = input.field->special;
        return (special == edit::SpecialField::Texture && material.texture.texture == current.material.texture.texture) ||
               (special == edit::SpecialField::BumpMap && material.bumpMap.texture == current.material.bumpMap.texture);
    });
    apply(*impl_, edit::SetFields{objectNode(id), std::move(fields)});
}

void Scene::setObjectToWorld(int id, const Transform& objectToWorld) {
    apply(*impl_, edit::SetFields{objectNode(id), {{edit::findField(edit::FieldOwner::Object, "world"),
                                                    toInternal(objectToWorld), {}}}});
}

void Scene::removeObject(int id) { apply(*impl_, edit::DeleteNodes{{objectNode(id)}}); }

std::vector<SceneNode> Scene::nodes() const {
    std::vector<SceneNode> nodes;
    ray::forEachBlock(walkable(*impl_), [&](ray::Block& block, const ray::DocumentPlace& place) {
        SceneNode node{block.id, place.path, toPublic(block.toParent), {}};
        for (const ray::SceneItem& item : block.items)
            if (const auto* master = std::get_if<ray::MasterReference>(&item)) node.masters.push_back(master->name);
        nodes.push_back(std::move(node));
    });
    return nodes;
}

void Scene::setNodeTransform(int nodeId, const Transform& toParent) {
    apply(*impl_, edit::SetFields{{edit::NodeKind::Block, nodeId},
                                  {matrixTransform("transform", edit::FieldOwner::Block, toParent)}});
}

std::vector<Light> Scene::lights() const {
    std::vector<Light> lights;
    for (const ray::Light& light : impl_->document().lights) lights.push_back(external(light));
    return lights;
}

void Scene::setLight(size_t index, const Light& light) {
    const edit::NodeId node = lightNode(*impl_, index);
    ray::Light l = internal(light);
    l.radius = impl_->document().lights[index].radius;  // read and kept, not in the API
    checkEveryField(l);
    apply(*impl_, edit::SetFields{node, edit::lightFields(l)});
}

void Scene::removeLight(size_t index) { apply(*impl_, edit::DeleteNodes{{lightNode(*impl_, index)}}); }

std::string Scene::toText() const {
    const ray::SceneDocument& document = impl_->document();
    const std::filesystem::path anchor = document.file.empty() ? "scene.xml" : document.file;
    return detail::translatingErrors(
        [&] { return ray::documentToText(document, impl_->session.resources(), anchor); });
}

void Scene::save(const std::filesystem::path& file) const { save(file, WriteOptions{}); }

void Scene::save(const std::filesystem::path& file, const WriteOptions& options) const {
    const std::filesystem::path key = fileKey(file);
    auto known = impl_->files.find(key);
    if (known != impl_->files.end() && !options.overwriteChanges) {
        if (const std::optional<std::string> change = edit::changeSince(known->second, file))
            badInput(file.string() + " " + *change + ": not saved, so that that change is not lost; load it again, or "
                     "save with overwrite_changes=True (C++: WriteOptions::overwriteChanges) to replace it");
    }
    detail::translatingErrors([&] {
        ray::saveDocument(impl_->document(), impl_->session.resources(), file, detail::writeOptionsOf(options));
    });
    impl_->files[key] = edit::stampOf(file);
}

// ---------------------------------------------------------------------------------------
// The one edit model, by node id and field name

std::vector<OutlineEntry> Scene::outline() const {
    std::vector<OutlineEntry> entries;
    for (const edit::OutlineEntry& entry : impl_->session.outline()) entries.push_back(toPublic(entry));
    return entries;
}

FieldValue Scene::field(const NodeId& node, const std::string& name) const {
    const edit::NodeId id = detail::nodeFrom(node);
    return detail::translatingErrors([&]() -> FieldValue {
        const edit::NodeView view = impl_->session.describe(id);
        for (const auto& [field, value] : view.fields)
            if (field->name == name || field->keyword() == name) return toPublic(value);
        badInput("a " + std::string(edit::nodeKindName(id.kind)) + " " + node + " has no field '" +
                 quotedForMessage(name, 60) + "'");
    });
}

EditResult Scene::set(const NodeId& node, const FieldValues& fields) {
    const edit::NodeId id = detail::nodeFrom(node);
    return toPublic(apply(*impl_, edit::SetFields{id, detail::inputsFrom(id.kind, fields)}));
}

EditResult Scene::add(const std::string& shape, const FieldValues& fields, const NodeId& parent,
                      const std::filesystem::path& meshFile) {
    edit::AddPrimitive add;
    const std::vector<std::string_view>& shapes = edit::shapeNames();
    auto known = std::find(shapes.begin(), shapes.end(), shape);
    if (known == shapes.end())
        badInput("add: the shape is cube, cylinder, cone, sphere, torus or mesh, not '" + quotedForMessage(shape, 40) + "'");
    static const ray::PrimitiveType kShapes[] = {ray::PrimitiveType::Cube, ray::PrimitiveType::Cylinder,
                                                 ray::PrimitiveType::Cone, ray::PrimitiveType::Sphere,
                                                 ray::PrimitiveType::Torus, ray::PrimitiveType::Mesh};
    add.shape = kShapes[known - shapes.begin()];
    add.meshFile = meshFile.string();
    if (add.shape == ray::PrimitiveType::Mesh && add.meshFile.empty()) badInput("add: a mesh needs its .obj file");
    if (!parent.empty()) add.parent = detail::nodeFrom(parent);
    add.fields = detail::inputsFrom(edit::FieldOwner::Object, fields);
    return toPublic(apply(*impl_, add));
}

EditResult Scene::addLight(const std::string& type, const FieldValues& fields) {
    const std::vector<std::string_view>& types = edit::lightTypeNames();
    auto known = std::find(types.begin(), types.end(), type);
    if (known == types.end())
        badInput("addLight: the type is point, directional, spot or area, not '" + quotedForMessage(type, 40) + "'");
    return toPublic(apply(*impl_, edit::AddLight{ray::LightType(known - types.begin()),
                                                 detail::inputsFrom(edit::FieldOwner::Light, fields)}));
}

namespace {

std::vector<edit::NodeId> nodesFrom(const std::vector<NodeId>& nodes) {
    std::vector<edit::NodeId> ids;
    for (const NodeId& node : nodes) ids.push_back(detail::nodeFrom(node));
    return ids;
}

}  // namespace

EditResult Scene::remove(const std::vector<NodeId>& nodes) {
    return toPublic(apply(*impl_, edit::DeleteNodes{nodesFrom(nodes)}));
}

EditResult Scene::duplicate(const std::vector<NodeId>& nodes) {
    return toPublic(apply(*impl_, edit::DuplicateNodes{nodesFrom(nodes)}));
}

EditResult Scene::group(const std::vector<NodeId>& nodes) {
    return toPublic(apply(*impl_, edit::GroupNodes{nodesFrom(nodes)}));
}

EditResult Scene::rename(const NodeId& tree, const std::string& name) {
    return set(tree, {{"name", name}});
}

EditResult Scene::makeUnique(const NodeId& placement) {
    return toPublic(apply(*impl_, edit::MakeUnique{detail::nodeFrom(placement)}));
}

}  // namespace ray::api
