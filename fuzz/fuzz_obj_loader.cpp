// libFuzzer target: Wavefront OBJ text through the mesh loader (tinyobjloader, then ray's
// triangulation, normals, texture coordinates and bounds), then the reference renderer's
// mesh BVH and a few rays through it.
//
// Anything but a clean InputError is a crash. Seeds: the course's meshes and ours.
#include <cmath>
#include <cstdint>
#include <string>

#include "scene/mesh.h"
#include "reference/mesh_intersector.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        ray::TriangleMesh mesh = ray::parseObjMesh(text, "fuzzed.obj");
        for (size_t t = 0; t < mesh.triangles.size() && t < 64; ++t) {
            (void)mesh.texCoordAt(t, 0.25, 0.25);
            (void)mesh.uTangent(t);
        }
        ray::MeshIntersector intersector(mesh);
        const ray::Vec3 centre = (mesh.boundsLo + mesh.boundsHi) * 0.5;
        for (const ray::Vec3& direction : {ray::Vec3{0, 0, -1}, ray::Vec3{0.3, -1, 0.2}, ray::Vec3{1, 0, 0}})
            (void)intersector.intersect(centre - direction * 10.0, direction, 1e-9, INFINITY);
    } catch (const ray::InputError&) {
    }
    return 0;
}
