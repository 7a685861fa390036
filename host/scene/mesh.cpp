#include "scene/mesh.h"

#include "core/input_file.h"
#include "scene/obj_material_library.h"
#include "scene/obj_reader.h"
#include "scene/scene.h"

namespace ray {

namespace {

// An OBJ is text: a line or two a vertex or face, so 1 GiB is tens of millions of
// triangles, more than a scene's memory check lets one mesh have.
constexpr InputLimit kObjFileLimit{"a mesh (OBJ)", uint64_t(1) << 30, "tens of millions of triangles of text"};

}  // namespace

Vec3 TriangleMesh::faceNormal(size_t triangle) const {
    Vec3 n = cross(corner(triangle, 1) - corner(triangle, 0), corner(triangle, 2) - corner(triangle, 0));
    double len = length(n);
    return len > 0 ? n / len : Vec3{};
}

Vec3 TriangleMesh::shadingNormal(size_t triangle, double b1, double b2) const {
    const std::array<MeshCorner, 3>& t = triangles[triangle];
    if (t[0].normal < 0 || t[1].normal < 0 || t[2].normal < 0) return faceNormal(triangle);
    Vec3 n = (1 - b1 - b2) * normals[size_t(t[0].normal)] + b1 * normals[size_t(t[1].normal)] +
             b2 * normals[size_t(t[2].normal)];
    double len = length(n);
    return len > 0 ? n / len : faceNormal(triangle);
}

std::array<double, 2> TriangleMesh::texCoordAt(size_t triangle, double b1, double b2) const {
    const std::array<MeshCorner, 3>& t = triangles[triangle];
    if (t[0].texCoord < 0 || t[1].texCoord < 0 || t[2].texCoord < 0) return {0, 0};
    const auto &a = texCoords[size_t(t[0].texCoord)], &b = texCoords[size_t(t[1].texCoord)],
               &c = texCoords[size_t(t[2].texCoord)];
    double b0 = 1 - b1 - b2;
    return {b0 * a[0] + b1 * b[0] + b2 * c[0], b0 * a[1] + b1 * b[1] + b2 * c[1]};
}

namespace {

// The texture coordinates' edges of a triangle: (du1, dv1) from corner 0 to 1, (du2, dv2)
// from 0 to 2, and det = du1·dv2 − du2·dv1; nullopt without vt.
struct UvEdges {
    double du1, dv1, du2, dv2, det;
};

std::optional<UvEdges> uvEdges(const TriangleMesh& mesh, size_t triangle) {
    const std::array<MeshCorner, 3>& t = mesh.triangles[triangle];
    if (t[0].texCoord < 0 || t[1].texCoord < 0 || t[2].texCoord < 0) return std::nullopt;
    const auto &a = mesh.texCoords[size_t(t[0].texCoord)], &b = mesh.texCoords[size_t(t[1].texCoord)],
               &c = mesh.texCoords[size_t(t[2].texCoord)];
    UvEdges e{b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1], 0};
    e.det = e.du1 * e.dv2 - e.du2 * e.dv1;
    return e;
}

}  // namespace

Vec3 TriangleMesh::uTangent(size_t triangle) const {
    auto e = uvEdges(*this, triangle);
    if (!e || e->det == 0) return {};
    Vec3 dpdu = (e->dv2 * (corner(triangle, 1) - corner(triangle, 0)) - e->dv1 * (corner(triangle, 2) - corner(triangle, 0))) /
                e->det;
    double len = length(dpdu);
    return len > 0 ? dpdu / len : Vec3{};
}

// ∂p/∂u × ∂p/∂v = (e1 × e2) / det for the position edges e1, e2, so the pair is
// right-handed about the face normal exactly when det > 0.
double TriangleMesh::uvHandedness(size_t triangle) const {
    auto e = uvEdges(*this, triangle);
    return e && e->det < 0 ? -1.0 : 1.0;
}

void TriangleMesh::computeBounds() {
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const auto& t : triangles)
        for (const MeshCorner& c : t) {
            lo = componentMin(lo, positions[size_t(c.position)]);
            hi = componentMax(hi, positions[size_t(c.position)]);
        }
    boundsLo = lo;
    boundsHi = hi;
}

TriangleMesh loadObjMesh(const std::filesystem::path& file) {
    std::string text;
    try {
        text = readInputFile(file, kObjFileLimit);
    } catch (const InputFileError& e) {
        throw InputError(file.string() + ": error: " + e.reason());
    }
    return parseObjMesh(text, file.string(), file.parent_path().empty() ? "." : file.parent_path());
}

TriangleMesh parseObjMesh(const std::string& objText, const std::string& nameForErrors,
                          const std::optional<std::filesystem::path>& folder) {
    if (!folder) return readObjMesh(objText, nameForErrors);
    ConfinedMaterialReader materials(*folder);
    ObjReadOptions options;
    options.materials = &materials;
    options.librariesRead = [&] {
        if (materials.refusal()) throw InputError(nameForErrors + ": error: " + *materials.refusal());
    };
    return readObjMesh(objText, nameForErrors, options);
}

}  // namespace ray
