// Triangle meshes: Wavefront OBJ files read by scene/obj_reader.h, in parallel, as
// tinyobjloader read them (SPEC §2: stored as given, not rescaled; polygons triangulated;
// `vn` gives smooth shading and `vt` texture coordinates, else the face normal and (0, 0)).
//
// A mesh is stored once however many primitives (masters) name its file: instances refer
// to it by index (PrimitiveInstance::mesh into Scene::meshes).
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/math.h"

namespace ray {

// One corner of a triangle: indices into the mesh's arrays; -1 where the face gave none.
struct MeshCorner {
    int position = 0;
    int normal = -1;
    int texCoord = -1;
};

struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;                    // as in the file (normalized on use)
    std::vector<std::array<double, 2>> texCoords; // (u, v)
    std::vector<std::array<MeshCorner, 3>> triangles;
    Vec3 boundsLo{0, 0, 0}, boundsHi{0, 0, 0};    // object-space box around every position

    // The corner positions of triangle i.
    const Vec3& corner(size_t triangle, int k) const { return positions[size_t(triangles[triangle][k].position)]; }
    // The unit face normal (counter-clockwise corners seen from the front), zero when the
    // triangle is degenerate.
    Vec3 faceNormal(size_t triangle) const;
    // The shading normal at barycentric (b1, b2) (weights of corners 1 and 2): the
    // interpolated vn where all three corners have one, else the face normal.
    Vec3 shadingNormal(size_t triangle, double b1, double b2) const;
    // The texture coordinates at (b1, b2); (0, 0) without vt.
    std::array<double, 2> texCoordAt(size_t triangle, double b1, double b2) const;
    // The unit direction in which u grows over the triangle (∂p/∂u from its vt), for bump
    // mapping; zero without vt or where the vt are degenerate.
    Vec3 uTangent(size_t triangle) const;
    // +1 where v grows along faceNormal × uTangent, as it does for texture coordinates laid
    // on the face's front counter-clockwise; −1 where they are mirrored (symmetric models
    // often mirror half their texture), so that bump mapping's B, the direction of growing
    // v, is −(N × T) there. +1 without vt or where they are degenerate.
    double uvHandedness(size_t triangle) const;
    void computeBounds();
    // What the arrays above hold, in bytes (--stats: a mesh's bytes a triangle).
    size_t memoryBytes() const {
        return positions.size() * sizeof(Vec3) + normals.size() * sizeof(Vec3) +
               texCoords.size() * sizeof(texCoords[0]) + triangles.size() * sizeof(triangles[0]);
    }
};

// Reads an OBJ file through core/input_file.h (a regular file of at most 1 GiB);
// InputError ("file: error: what") when it cannot be read or holds no triangles. Materials
// are ignored (the scene file gives the material), but an `mtllib` is read, from the OBJ's
// folder only (scene/obj_material_library.h): one outside it, or not a regular file of a
// library's size, is an InputError.
TriangleMesh loadObjMesh(const std::filesystem::path& file);
// The same from text (tests, fuzzing). With `folder`, mtllib lines are read as an OBJ in
// that folder would have them read; without, they are passed over.
TriangleMesh parseObjMesh(const std::string& objText, const std::string& nameForErrors,
                          const std::optional<std::filesystem::path>& folder = std::nullopt);

}  // namespace ray
