// The public Scene (include/ray/scene.h): a scene document (scene/scene_document.h) and
// the internal flattened Scene made from it.
//
// Every edit of the document runs on a copy, which is flattened and only then kept: an
// edit that fails (a bad value, an object since removed, a csg operand left empty)
// changes nothing. Adding a primitive, a light, a camera or globals changes the flattened
// scene in place, as flattening would (a primitive added in code is a transblock of its
// own at the end of the root tree, so its instance comes last): scenes built in code add
// primitives by the thousand.
#include "ray/scene.h"

#include <atomic>
#include <cmath>
#include <map>

#include "api/camera_conversion.h"
#include "api/error_translation.h"
#include "api/input_checks.h"
#include "api/scene_impl.h"
#include "core/math.h"
#include "image/image.h"
#include "scene/file_search.h"
#include "scene/scene_loader.h"

namespace ray::api {

namespace {

ray::Vec3 internal(Vec3 v) { return detail::toInternal(v); }

ray::Affine internal(const Transform& t) {
    ray::Affine a;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) a.m[r][c] = t.m[r][c];
    return a;
}

Transform external(const ray::Affine& a) {
    Transform t;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.m[r][c] = a.m[r][c];
    return t;
}

ray::TextureMap internal(const TextureUse& use) { return {use.texture, use.repeatU, use.repeatV}; }

Vec3 external(const ray::Vec3& v) { return detail::toPublic(v); }

ray::Material internal(const Material& material) {
    ray::Material m;
    m.diffuse = internal(material.diffuse);
    m.ambient = internal(material.ambient);
    m.specular = internal(material.specular);
    m.reflective = internal(material.reflective);
    m.transparent = internal(material.transparent);
    m.emissive = internal(material.emissive);
    m.shininess = material.shininess;
    m.ior = material.ior;
    m.blend = material.blend;
    m.texture = internal(material.texture);
    m.bumpMap = internal(material.bumpMap);
    return m;
}

Material external(const ray::Material& m) {
    Material material;
    material.diffuse = external(m.diffuse);
    material.ambient = external(m.ambient);
    material.specular = external(m.specular);
    material.reflective = external(m.reflective);
    material.transparent = external(m.transparent);
    material.emissive = external(m.emissive);
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
    l.color = internal(light.color);
    l.attenuation = internal(light.attenuation);
    l.position = internal(light.position);
    l.direction = internal(light.direction);
    l.angleDegrees = light.angleDegrees;
    l.penumbraDegrees = light.penumbraDegrees;
    l.width = light.width;
    l.height = light.height;
    return l;
}

Light external(const ray::Light& l) {
    Light light;
    light.type = LightType(int(l.type));
    light.color = external(l.color);
    light.attenuation = external(l.attenuation);
    light.position = external(l.position);
    light.direction = external(l.direction);
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

// The inverse of a transform given for an object or a transblock; singular: InputError.
ray::Affine invertible(const ray::Affine& transform, const std::string& what) {
    const ray::TransformOp op = ray::TransformOp::matrix(transform);
    if (auto why = op.whySingular()) badInput(what + ": " + *why + " (a zero scale?); it must be invertible");
    return op.affine().second;
}

[[noreturn]] void noObject(int id) {
    badInput("object " + std::to_string(id) +
             " does not exist (removed, or never made); take ids from Scene::objects()");
}

ray::DocumentPlace placeOf(ray::SceneDocument& document, int id) {
    std::optional<ray::DocumentPlace> place = ray::findObject(document, id);
    if (!place) noObject(id);
    return *place;
}

ray::PrimitiveNode& objectAt(const ray::DocumentPlace& place) {
    return std::get<ray::PrimitiveNode>(place.block->items[place.item]);
}

// Where each object's instances are in a flattened scene: the first, and how many.
struct InstanceIndex {
    struct Entry {
        const ray::PrimitiveInstance* first = nullptr;
        size_t count = 0;
    };
    std::map<int, Entry> byObject;

    explicit InstanceIndex(const ray::Scene& scene, int only = -1) {
        for (const auto* list : {&scene.primitives, &scene.csgOperands})
            for (const ray::PrimitiveInstance& instance : *list) {
                if (instance.type == ray::PrimitiveType::Csg) continue;  // its operands count
                if (instance.sourceObject < 0 || (only >= 0 && instance.sourceObject != only)) continue;
                Entry& entry = byObject[instance.sourceObject];
                if (!entry.first) entry.first = &instance;
                ++entry.count;
            }
    }

    const Entry* find(int id) const {
        auto it = byObject.find(id);
        return it == byObject.end() ? nullptr : &it->second;
    }
};

// Object to world of the object's first instance, and its inverse; in its tree's frame
// when it has none.
std::pair<ray::Affine, ray::Affine> firstPlacement(const InstanceIndex& index, const ray::DocumentPlace& place,
                                                   int id) {
    if (const InstanceIndex::Entry* entry = index.find(id))
        return {entry->first->objectToWorld, entry->first->worldToObject};
    return ray::composedPlacement(place.blocks);
}

SceneObject describe(const ray::Scene& scene, const InstanceIndex& index,
                     const ray::PrimitiveNode& node, const ray::DocumentPlace& place) {
    SceneObject object;
    object.id = node.id;
    object.path = place.path;
    object.shape = Shape(int(node.type));  // same order as PrimitiveType (a primitive is never a csg)
    object.inMaster = place.tree->name != "root";
    const InstanceIndex::Entry* entry = index.find(node.id);
    object.instances = entry ? entry->count : 0;
    object.material = external(entry ? scene.materials[size_t(entry->first->material)] : node.material);
    object.objectToWorld = external(firstPlacement(index, place, node.id).first);
    return object;
}

}  // namespace

uint64_t Scene::Impl::newRevision() {
    static std::atomic<uint64_t> last{0};
    return ++last;
}

void Scene::Impl::edit(const std::function<void(ray::SceneDocument&)>& change) {
    detail::translatingErrors([&] {
        ray::SceneDocument changed = document;
        change(changed);
        ray::Scene flattened = ray::flattenDocument(changed, resources, options);
        document = std::move(changed);
        scene = std::move(flattened);
        this->changed();
    });
}

Transform Transform::translate(Vec3 t) {
    detail::checkFinite("translate", t);
    return external(ray::Affine::translation(internal(t)));
}
Transform Transform::scale(Vec3 s) {
    detail::checkFinite("scale", s);
    return external(ray::Affine::scaling(internal(s)));
}
Transform Transform::rotate(Vec3 axis, double angleDegrees) {
    detail::checkFinite("rotate's axis", axis);
    detail::checkFinite("rotate's angle", angleDegrees);
    if (axis.x == 0 && axis.y == 0 && axis.z == 0)
        badInput("rotate: the axis (0, 0, 0) has no direction; give a non-zero axis, such as (0, 1, 0)");
    return external(ray::Affine::rotation(internal(axis), angleDegrees));
}
Transform operator*(const Transform& a, const Transform& b) { return external(internal(a) * internal(b)); }

Scene::Scene() : impl_(std::make_unique<Impl>()) {}
Scene::~Scene() = default;
Scene::Scene(const Scene& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
Scene& Scene::operator=(const Scene& other) {
    if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
    return *this;
}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

namespace {

// Loads the document with `read`, flattens it, and keeps both in `impl`.
template <class Read>
void loadInto(Scene::Impl& impl, const LoadOptions& options, std::vector<std::string>& warnings, Read read) {
    detail::translatingErrors([&] {
        ray::LoadOptions load = internal(options, warnings);
        impl.document = read(load);
        impl.scene = ray::flattenDocument(impl.document, impl.resources, load);
        impl.changed();
        load.warn = [](const std::string&) {};  // what later flattenings find, loading reported
        impl.options = load;
    });
}

}  // namespace

LoadResult Scene::load(const std::filesystem::path& file, const LoadOptions& options) {
    LoadResult result;
    loadInto(*result.scene.impl_, options, result.warnings,
             [&](const ray::LoadOptions& load) { return ray::loadSceneDocument(file, load); });
    return result;
}

LoadResult Scene::fromString(const std::string& xml, const std::filesystem::path& name, const LoadOptions& options) {
    LoadResult result;
    loadInto(*result.scene.impl_, options, result.warnings,
             [&](const ray::LoadOptions& load) { return ray::loadSceneDocumentFromText(xml, name, load); });
    return result;
}

Camera Scene::camera() const { return detail::toPublic(impl_->scene.camera); }

void Scene::setCamera(const Camera& camera) {
    ray::Camera internalCamera = detail::toInternal(camera);
    detail::checkCamera(internalCamera);
    impl_->scene.camera = internalCamera;
    impl_->document.camera = internalCamera;  // not changed(): each frame reads the camera itself
}

Globals Scene::globals() const {
    const ray::GlobalCoefficients& g = impl_->scene.globals;
    return {g.ka, g.kd, g.ks, g.kt};
}

void Scene::setGlobals(const Globals& globals) {
    detail::checkGlobals(globals);
    impl_->scene.globals = {globals.ka, globals.kd, globals.ks, globals.kt};
    impl_->document.globals = impl_->scene.globals;
    impl_->changed();
}

void Scene::addLight(const Light& light) {
    detail::checkLight(light);
    impl_->scene.lights.push_back(internal(light));
    impl_->document.lights.push_back(internal(light));
    impl_->changed();
}

int Scene::addMaterial(const Material& material) {
    detail::checkMaterial(material);
    const size_t images = impl_->resources.images.size();
    if (material.texture.texture >= 0) checkIndex(material.texture.texture, images, "texture");
    if (material.bumpMap.texture >= 0) checkIndex(material.bumpMap.texture, images, "bump map texture");
    impl_->materials.push_back(internal(material));
    return int(impl_->materials.size() - 1);
}

int Scene::addTextureFromFile(const std::filesystem::path& file) {
    ray::Image image;
    try {
        image = ray::readImage(file);
    } catch (const ray::ImageError& e) {
        throw InputError(e.what(), file.string(), 0);
    }
    impl_->resources.images.push_back(image);
    impl_->resources.imageFiles.push_back(file);
    impl_->scene.images.push_back(std::move(image));
    impl_->scene.imageFiles.push_back(file);
    impl_->changed();
    return int(impl_->scene.images.size() - 1);
}

int Scene::addTextureFromPixels(int width, int height, const std::vector<float>& rgb) {
    if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3)
        badInput("a texture of " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                 "width*height*3 floats, not " + std::to_string(rgb.size()));
    ray::Image image(width, height);
    image.rgb = rgb;
    impl_->resources.images.push_back(image);
    impl_->resources.imageFiles.push_back("<memory>");
    impl_->scene.images.push_back(std::move(image));
    impl_->scene.imageFiles.push_back("<memory>");
    impl_->changed();
    return int(impl_->scene.images.size() - 1);
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
    impl_->resources.meshes.push_back(mesh);
    impl_->resources.meshFiles.push_back("<memory>");
    impl_->scene.meshes.push_back(std::move(mesh));
    impl_->scene.meshFiles.push_back("<memory>");
    impl_->changed();
    return int(impl_->scene.meshes.size() - 1);
}

// A transblock of its own at the end of the root tree, holding the object; its instance
// is appended to the flattened scene exactly as flattening would make it.
int Scene::addPrimitive(Shape shape, const Transform& objectToWorld, int material, int mesh) {
    checkIndex(material, impl_->materials.size(), "material");
    if (shape == Shape::Mesh) checkIndex(mesh, impl_->resources.meshes.size(), "mesh");
    invertible(internal(objectToWorld), "a primitive's transform");
    ray::SceneDocument& document = impl_->document;
    ray::PrimitiveNode node;
    node.type = ray::PrimitiveType(int(shape));  // same order as PrimitiveType
    node.id = document.nextObjectId;
    node.material = impl_->materials[size_t(material)];
    node.mesh = shape == Shape::Mesh ? mesh : -1;
    ray::Block block;
    block.id = document.nextBlockId;
    block.transforms.push_back(ray::TransformOp::matrix(internal(objectToWorld)));
    ray::composeBlock(block);

    ray::PrimitiveInstance instance;
    instance.type = node.type;
    instance.objectToWorld = ray::Affine::identity() * block.toParent;
    instance.worldToObject = block.fromParent * ray::Affine::identity();
    instance.material = int(impl_->scene.materials.size());
    instance.mesh = node.mesh;
    instance.sourceObject = node.id;
    ray::fitObjectBox(instance, impl_->resources.meshes);

    impl_->scene.materials.push_back(node.material);
    impl_->scene.primitives.push_back(instance);
    impl_->changed();
    ++document.nextObjectId;
    ++document.nextBlockId;
    ++document.primitiveElements;
    block.items.push_back(std::move(node));
    document.rootToSet().tree.blocks.push_back(std::move(block));
    return instance.sourceObject;
}

int Scene::addPrimitiveTo(int nodeId, Shape shape, const Transform& toNode, int material, int mesh) {
    checkIndex(material, impl_->materials.size(), "material");
    if (shape == Shape::Mesh) checkIndex(mesh, impl_->resources.meshes.size(), "mesh");
    invertible(internal(toNode), "a primitive's transform");
    int id = -1;
    impl_->edit([&](ray::SceneDocument& document) {
        std::optional<ray::DocumentPlace> place = ray::findBlock(document, nodeId);
        if (!place)
            badInput("transblock " + std::to_string(nodeId) + " does not exist; take ids from Scene::nodes()");
        ray::PrimitiveNode node;
        node.type = ray::PrimitiveType(int(shape));
        node.id = id = document.nextObjectId++;
        node.material = impl_->materials[size_t(material)];
        node.mesh = shape == Shape::Mesh ? mesh : -1;
        ++document.primitiveElements;
        ray::Block own;
        own.id = document.nextBlockId++;
        own.transforms.push_back(ray::TransformOp::matrix(internal(toNode)));
        ray::composeBlock(own);
        own.items.push_back(std::move(node));
        ray::TreeNode tree;
        tree.blocks.push_back(std::move(own));
        place->block->items.push_back(ray::Box<ray::TreeNode>(std::move(tree)));
    });
    return id;
}

size_t Scene::primitiveCount() const { return impl_->scene.primitives.size(); }
size_t Scene::lightCount() const { return impl_->scene.lights.size(); }

std::vector<SceneObject> Scene::objects() const {
    const InstanceIndex index(impl_->scene);
    std::vector<SceneObject> objects;
    ray::forEachObject(impl_->document, [&](ray::PrimitiveNode& node, const ray::DocumentPlace& place) {
        objects.push_back(describe(impl_->scene, index, node, place));
    });
    return objects;
}

SceneObject Scene::object(int id) const {
    ray::DocumentPlace place = placeOf(impl_->document, id);
    return describe(impl_->scene, InstanceIndex(impl_->scene, id), objectAt(place), place);
}

int Scene::objectOfInstance(size_t instance) const {
    const std::vector<ray::PrimitiveInstance>& primitives = impl_->scene.primitives;
    if (instance >= primitives.size())
        badInput("instance " + std::to_string(instance) + " does not exist (the scene renders " +
                 std::to_string(primitives.size()) + ")");
    return primitives[instance].sourceObject;
}

void Scene::setMaterial(int id, const Material& material) {
    detail::checkMaterial(material);
    const size_t images = impl_->resources.images.size();
    if (material.texture.texture >= 0) checkIndex(material.texture.texture, images, "texture");
    if (material.bumpMap.texture >= 0) checkIndex(material.bumpMap.texture, images, "bump map texture");
    const SceneObject current = object(id);
    impl_->edit([&](ray::SceneDocument& document) {
        ray::PrimitiveNode& node = objectAt(placeOf(document, id));
        const ray::TextureMap texture = node.material.texture, bumpMap = node.material.bumpMap;
        node.material = internal(material);
        // A texture the file names stays named by it (so a saved file names it as it did)
        // unless another one replaces it: then the handle's own file is written.
        if (node.files) {
            if (material.texture.texture != current.material.texture.texture) {
                node.files->texture.reset();
                node.files->missingTexture.clear();
            } else if (node.files->texture) {
                node.material.texture.image = texture.image;
            }
            if (material.bumpMap.texture != current.material.bumpMap.texture) {
                node.files->bumpMap.reset();
                node.files->missingBumpMap.clear();
            } else if (node.files->bumpMap) {
                node.material.bumpMap.image = bumpMap.image;
            }
        }
    });
}

void Scene::setObjectToWorld(int id, const Transform& objectToWorld) {
    const ray::Affine target = internal(objectToWorld);
    invertible(target, "the object's transform");
    const InstanceIndex index(impl_->scene, id);
    impl_->edit([&](ray::SceneDocument& document) {
        ray::DocumentPlace place = placeOf(document, id);
        const ray::Affine worldToObject = firstPlacement(index, place, id).second;
        ray::Block& block = *place.block;
        if (block.items.size() == 1) {
            // Alone in its transblock: the block takes B' = B · W · T, so that the first
            // instance, P · B', is T (P · B = W⁻¹).
            const ray::Affine toParent = block.toParent * worldToObject * target;
            invertible(toParent, "the object's transform, in its transblock's frame,");
            block.transforms = {ray::TransformOp::matrix(toParent)};
            ray::composeBlock(block);
            return;
        }
        // It shares its transblock: it gets one of its own, inside an inline tree.
        ray::Block own;
        own.id = document.nextBlockId++;
        const ray::Affine toParent = worldToObject * target;
        invertible(toParent, "the object's transform, in its transblock's frame,");
        own.transforms = {ray::TransformOp::matrix(toParent)};
        ray::composeBlock(own);
        own.items.push_back(std::move(block.items[place.item]));
        ray::TreeNode tree;
        tree.blocks.push_back(std::move(own));
        block.items[place.item] = ray::Box<ray::TreeNode>(std::move(tree));
    });
}

void Scene::removeObject(int id) {
    impl_->edit([&](ray::SceneDocument& document) {
        ray::DocumentPlace place = placeOf(document, id);
        place.block->items.erase(place.block->items.begin() + std::ptrdiff_t(place.item));
    });
}

std::vector<SceneNode> Scene::nodes() const {
    std::vector<SceneNode> nodes;
    ray::forEachBlock(impl_->document, [&](ray::Block& block, const ray::DocumentPlace& place) {
        SceneNode node{block.id, place.path, external(block.toParent), {}};
        for (const ray::SceneItem& item : block.items)
            if (const auto* master = std::get_if<ray::MasterReference>(&item)) node.masters.push_back(master->name);
        nodes.push_back(std::move(node));
    });
    return nodes;
}

void Scene::setNodeTransform(int nodeId, const Transform& toParent) {
    invertible(internal(toParent), "the transblock's transform");
    impl_->edit([&](ray::SceneDocument& document) {
        std::optional<ray::DocumentPlace> place = ray::findBlock(document, nodeId);
        if (!place)
            badInput("transblock " + std::to_string(nodeId) + " does not exist; take ids from Scene::nodes()");
        place->block->transforms = {ray::TransformOp::matrix(internal(toParent))};
        ray::composeBlock(*place->block);
    });
}

std::vector<Light> Scene::lights() const {
    std::vector<Light> lights;
    for (const ray::Light& light : impl_->document.lights) lights.push_back(external(light));
    return lights;
}

void Scene::setLight(size_t index, const Light& light) {
    checkIndex(int(std::min<size_t>(index, size_t(INT32_MAX))), impl_->document.lights.size(), "light");
    detail::checkLight(light);
    ray::Light l = internal(light);
    l.radius = impl_->document.lights[index].radius;  // read and kept, not in the API
    impl_->document.lights[index] = l;
    impl_->scene.lights[index] = l;
    impl_->changed();
}

void Scene::removeLight(size_t index) {
    checkIndex(int(std::min<size_t>(index, size_t(INT32_MAX))), impl_->document.lights.size(), "light");
    ray::removeLight(impl_->document, index);  // and the element it was read from, with it
    impl_->scene.lights.erase(impl_->scene.lights.begin() + std::ptrdiff_t(index));
    impl_->changed();
}

std::string Scene::toText() const {
    const std::filesystem::path anchor = impl_->document.file.empty() ? "scene.xml" : impl_->document.file;
    return detail::translatingErrors([&] { return ray::documentToText(impl_->document, impl_->resources, anchor); });
}

void Scene::save(const std::filesystem::path& file) const {
    detail::translatingErrors([&] { ray::saveDocument(impl_->document, impl_->resources, file); });
}

}  // namespace ray::api
