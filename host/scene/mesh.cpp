#include "scene/mesh.h"

#include <cctype>
#include <map>
#include <optional>
#include <sstream>

#include <tiny_obj_loader.h>

#include "core/input_file.h"
#include "scene/scene.h"

namespace ray {

namespace {

// The n of a line ending "line n", "line n." or "line n.)" (tinyobjloader's way of saying
// where), read by hand: no std::regex on text from outside (a long line overflowed its
// recursion).
std::optional<std::string> trailingLineNumber(const std::string& line) {
    size_t end = line.find_last_not_of(" \t\r");
    if (end == std::string::npos) return std::nullopt;
    if (line[end] == ')') --end;
    if (end != std::string::npos && line[end] == '.') --end;
    size_t begin = end + 1;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(line[begin - 1]))) --begin;
    if (begin > end || begin < 5 || line.compare(begin - 5, 5, "line ") != 0) return std::nullopt;
    return line.substr(begin, end + 1 - begin);
}

// tinyobjloader's error text: one or more lines such as "Failed parse `f' line(e.g. zero
// value for face index. line 2.)". Each becomes "file:line: error: ...", the form of the
// scene loader's messages, so no line of it is left without its file.
std::string describeObjErrors(const std::string& errors, const std::string& name) {
    std::istringstream lines(errors);
    std::string out, line;
    while (std::getline(lines, line)) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const std::optional<std::string> number = trailingLineNumber(line);
        const std::string where = number ? name + ":" + *number : name;
        out += (out.empty() ? "" : "\n") + where + ": error: cannot read the OBJ file: " + line;
    }
    if (out.empty()) out = name + ": error: cannot read the OBJ file";
    return out + "\n(check that " + name + " is a Wavefront OBJ file)";
}

// What tinyobjloader made of an OBJ's text.
struct ParsedObj {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;  // read (so that a bad library is found), not used
    std::string warnings, errors;
    bool valid = false;
};

TriangleMesh fromParsed(const ParsedObj& parsed, const std::string& name) {
    if (!parsed.valid) throw InputError(describeObjErrors(parsed.errors, name));
    const tinyobj::attrib_t& attrib = parsed.attrib;
    TriangleMesh mesh;
    mesh.positions.reserve(attrib.vertices.size() / 3);
    for (size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)
        mesh.positions.push_back({attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]});
    for (size_t i = 0; i + 2 < attrib.normals.size(); i += 3)
        mesh.normals.push_back({attrib.normals[i], attrib.normals[i + 1], attrib.normals[i + 2]});
    for (size_t i = 0; i + 1 < attrib.texcoords.size(); i += 2)
        mesh.texCoords.push_back({attrib.texcoords[i], attrib.texcoords[i + 1]});

    for (const tinyobj::shape_t& shape : parsed.shapes) {
        const std::vector<tinyobj::index_t>& indices = shape.mesh.indices;
        // Triangulated by the reader: three indices a face.
        for (size_t i = 0; i + 2 < indices.size(); i += 3) {
            std::array<MeshCorner, 3> triangle;
            bool valid = true;
            for (int k = 0; k < 3; ++k) {
                const tinyobj::index_t& index = indices[i + size_t(k)];
                valid = valid && index.vertex_index >= 0 && size_t(index.vertex_index) < mesh.positions.size();
                triangle[k].position = index.vertex_index;
                triangle[k].normal = index.normal_index >= 0 && size_t(index.normal_index) < mesh.normals.size()
                                         ? index.normal_index : -1;
                triangle[k].texCoord =
                    index.texcoord_index >= 0 && size_t(index.texcoord_index) < mesh.texCoords.size()
                        ? index.texcoord_index : -1;
            }
            if (!valid)
                throw InputError(name + ": error: a face names a vertex that does not exist; check the file");
            mesh.triangles.push_back(triangle);
        }
    }
    if (mesh.triangles.empty())
        throw InputError(name + ": error: the OBJ file holds no faces; a mesh needs at least one triangle");
    mesh.computeBounds();
    return mesh;
}

// An OBJ is text: a line or two a vertex or face, so 1 GiB is tens of millions of
// triangles, more than a scene's memory check lets one mesh have.
constexpr InputLimit kObjFileLimit{"a mesh (OBJ)", uint64_t(1) << 30, "tens of millions of triangles of text"};
// A material library is a few lines a material.
constexpr InputLimit kMaterialLibraryLimit{"a material library (mtllib)", uint64_t(16) << 20,
                                           "the text of thousands of materials"};

// An OBJ's `mtllib` names, read from the OBJ's own folder and nowhere else: an OBJ comes from
// anywhere, and its library could name /dev/zero, a FIFO or another user's files. ray takes
// no material from a library (the scene gives the material), so one that is missing is
// passed over as before; one outside the folder, or not a regular file of a library's
// size, is refused with the reason (the mesh is refused with it).
class ConfinedMaterialReader : public tinyobj::MaterialReader {
public:
    explicit ConfinedMaterialReader(std::filesystem::path folder) : folder_(std::move(folder)) {}

    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* materialMap, std::string* warn, std::string* err) override {
        if (refusal_) return false;
        namespace fs = std::filesystem;
        std::error_code ec;
        const fs::path folder = fs::weakly_canonical(folder_, ec);
        const fs::path candidate = folder_ / fs::path(name);
        const fs::path real = fs::weakly_canonical(candidate, ec);
        const fs::path inside = real.lexically_relative(folder);
        if (fs::path(name).is_absolute() || ec || inside.empty() || *inside.begin() == "..") {
            refusal_ = "mtllib '" + name + "' is outside the OBJ's folder; ray reads a material library only from the " +
                       "OBJ's own folder (and uses none of its materials): remove the mtllib line or move the file";
            return false;
        }
        if (!fs::exists(fs::symlink_status(candidate, ec))) return false;  // missing: no materials, as ever
        try {
            std::istringstream text(readInputFile(candidate, kMaterialLibraryLimit));
            tinyobj::LoadMtl(materialMap, materials, &text, warn, err);
        } catch (const InputFileError& e) {
            refusal_ = "mtllib '" + name + "' (" + candidate.string() + "): " + e.reason();
            return false;
        }
        return true;
    }

    // Why a library was refused, if one was.
    const std::optional<std::string>& refusal() const { return refusal_; }

private:
    std::filesystem::path folder_;
    std::optional<std::string> refusal_;
};

// The OBJ text parsed, polygons triangulated (fans); `materials` reads its mtllib lines, or
// nothing reads them (nullptr).
ParsedObj parseObj(const std::string& text, tinyobj::MaterialReader* materials) {
    ParsedObj parsed;
    std::istringstream in(text);
    parsed.valid = tinyobj::LoadObj(&parsed.attrib, &parsed.shapes, &parsed.materials, &parsed.warnings,
                                    &parsed.errors, &in, materials, /*triangulate=*/true,
                                    /*default_vcols_fallback=*/false);
    return parsed;
}

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
    if (!folder) return fromParsed(parseObj(objText, nullptr), nameForErrors);
    ConfinedMaterialReader materials(*folder);
    ParsedObj parsed = parseObj(objText, &materials);
    if (materials.refusal()) throw InputError(nameForErrors + ": error: " + *materials.refusal());
    return fromParsed(parsed, nameForErrors);
}

}  // namespace ray
