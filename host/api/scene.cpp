// The public Scene (include/ray/scene.h) over the internal flattened Scene.
#include "ray/scene.h"

#include <cmath>

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

}  // namespace

Transform Transform::translate(Vec3 t) { return external(ray::Affine::translation(internal(t))); }
Transform Transform::scale(Vec3 s) { return external(ray::Affine::scaling(internal(s))); }
Transform Transform::rotate(Vec3 axis, double angleDegrees) {
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

LoadResult Scene::load(const std::filesystem::path& file, const LoadOptions& options) {
    LoadResult result;
    result.scene.impl_->scene = detail::translatingErrors(
        [&] { return ray::loadScene(file, internal(options, result.warnings)); });
    return result;
}

LoadResult Scene::fromString(const std::string& xml, const std::filesystem::path& name, const LoadOptions& options) {
    LoadResult result;
    result.scene.impl_->scene = detail::translatingErrors(
        [&] { return ray::loadSceneFromText(xml, name, internal(options, result.warnings)); });
    return result;
}

Camera Scene::camera() const { return detail::toPublic(impl_->scene.camera); }

void Scene::setCamera(const Camera& camera) {
    ray::Camera internalCamera = detail::toInternal(camera);
    detail::checkCamera(internalCamera);
    impl_->scene.camera = internalCamera;
}

Globals Scene::globals() const {
    const ray::GlobalCoefficients& g = impl_->scene.globals;
    return {g.ka, g.kd, g.ks, g.kt};
}

void Scene::setGlobals(const Globals& globals) {
    impl_->scene.globals = {globals.ka, globals.kd, globals.ks, globals.kt};
}

void Scene::addLight(const Light& light) {
    detail::checkLight(light);
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
    impl_->scene.lights.push_back(l);
}

int Scene::addMaterial(const Material& material) {
    detail::checkMaterial(material);
    const size_t images = impl_->scene.images.size();
    if (material.texture.texture >= 0) checkIndex(material.texture.texture, images, "texture");
    if (material.bumpMap.texture >= 0) checkIndex(material.bumpMap.texture, images, "bump map texture");
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
    impl_->scene.materials.push_back(m);
    return int(impl_->scene.materials.size() - 1);
}

int Scene::addTextureFromFile(const std::filesystem::path& file) {
    ray::Image image;
    try {
        image = ray::readImage(file);
    } catch (const ray::ImageError& e) {
        throw InputError(e.what(), file.string(), 0);
    }
    impl_->scene.images.push_back(std::move(image));
    impl_->scene.imageFiles.push_back(file);
    return int(impl_->scene.images.size() - 1);
}

int Scene::addTextureFromPixels(int width, int height, const std::vector<float>& rgb) {
    if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3)
        badInput("a texture of " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                 "width*height*3 floats, not " + std::to_string(rgb.size()));
    ray::Image image(width, height);
    image.rgb = rgb;
    impl_->scene.images.push_back(std::move(image));
    impl_->scene.imageFiles.push_back("<memory>");
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
    impl_->scene.meshes.push_back(std::move(mesh));
    impl_->scene.meshFiles.push_back("<memory>");
    return int(impl_->scene.meshes.size() - 1);
}

void Scene::addPrimitive(Shape shape, const Transform& objectToWorld, int material, int mesh) {
    checkIndex(material, impl_->scene.materials.size(), "material");
    if (shape == Shape::Mesh) checkIndex(mesh, impl_->scene.meshes.size(), "mesh");
    ray::PrimitiveInstance instance;
    instance.type = ray::PrimitiveType(int(shape));  // same order as PrimitiveType
    instance.objectToWorld = internal(objectToWorld);
    instance.worldToObject = instance.objectToWorld.inverse();
    if (!std::isfinite(instance.worldToObject.m[0][0]))
        badInput("a primitive's transform is singular (a zero scale?); it must be invertible");
    instance.material = material;
    instance.mesh = shape == Shape::Mesh ? mesh : -1;
    ray::fitObjectBox(instance, impl_->scene.meshes);
    impl_->scene.primitives.push_back(instance);
}

size_t Scene::primitiveCount() const { return impl_->scene.primitives.size(); }
size_t Scene::lightCount() const { return impl_->scene.lights.size(); }

}  // namespace ray::api
