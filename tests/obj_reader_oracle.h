// The OBJ reading that scene/obj_reader.h replaced, kept as the oracle it is held to:
// tinyobjloader's LoadObj (triangulating, mtllib through the same confined reader) and the
// conversion mesh.cpp made of its output, with the same error texts. Used by
// tests/test_obj_reader.cpp and fuzz/fuzz_obj_loader.cpp, which compare the two bit for bit.
#pragma once

#include <bit>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <tiny_obj_loader.h>

#include "scene/mesh.h"
#include "scene/obj_material_library.h"
#include "scene/obj_reader.h"
#include "scene/scene.h"

namespace ray::oracle {

inline std::optional<std::string> trailingLineNumber(const std::string& line) {
    size_t end = line.find_last_not_of(" \t\r");
    if (end == std::string::npos) return std::nullopt;
    if (line[end] == ')') --end;
    if (end != std::string::npos && line[end] == '.') --end;
    size_t begin = end + 1;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(line[begin - 1]))) --begin;
    if (begin > end || begin < 5 || line.compare(begin - 5, 5, "line ") != 0) return std::nullopt;
    return line.substr(begin, end + 1 - begin);
}

inline std::string describeObjErrors(const std::string& errors, const std::string& name) {
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

struct ParsedObj {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warnings, errors;
    bool valid = false;
};

inline TriangleMesh fromParsed(const ParsedObj& parsed, const std::string& name) {
    if (!parsed.valid) throw InputError(describeObjErrors(parsed.errors, name));
    const tinyobj::attrib_t& attrib = parsed.attrib;
    TriangleMesh mesh;
    for (size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)
        mesh.positions.push_back({attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]});
    for (size_t i = 0; i + 2 < attrib.normals.size(); i += 3)
        mesh.normals.push_back({attrib.normals[i], attrib.normals[i + 1], attrib.normals[i + 2]});
    for (size_t i = 0; i + 1 < attrib.texcoords.size(); i += 2)
        mesh.texCoords.push_back({attrib.texcoords[i], attrib.texcoords[i + 1]});
    for (const tinyobj::shape_t& shape : parsed.shapes) {
        const std::vector<tinyobj::index_t>& indices = shape.mesh.indices;
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

inline ParsedObj parseObj(const std::string& text, tinyobj::MaterialReader* materials) {
    ParsedObj parsed;
    std::istringstream in(text);
    parsed.valid = tinyobj::LoadObj(&parsed.attrib, &parsed.shapes, &parsed.materials, &parsed.warnings,
                                    &parsed.errors, &in, materials, /*triangulate=*/true,
                                    /*default_vcols_fallback=*/false);
    return parsed;
}

// parseObjMesh as it was.
inline TriangleMesh parseObjMesh(const std::string& objText, const std::string& nameForErrors,
                                 const std::optional<std::filesystem::path>& folder = std::nullopt) {
    if (!folder) return fromParsed(parseObj(objText, nullptr), nameForErrors);
    ConfinedMaterialReader materials(*folder);
    ParsedObj parsed = parseObj(objText, &materials);
    if (materials.refusal()) throw InputError(nameForErrors + ": error: " + *materials.refusal());
    return fromParsed(parsed, nameForErrors);
}

// What a reading gave: the mesh, or the error's text.
struct Outcome {
    std::optional<TriangleMesh> mesh;
    std::string error;
};

template <class Read>
Outcome outcomeOf(const Read& read) {
    try {
        return {read(), {}};
    } catch (const InputError& e) {
        return {std::nullopt, e.what()};
    }
}

// The new reading as parseObjMesh makes it, the text cut into `chunks` pieces (0: as the
// reader chooses).
inline Outcome cutReading(const std::string& text, const std::string& name,
                          const std::optional<std::filesystem::path>& folder, int chunks) {
    return outcomeOf([&] {
        std::optional<ConfinedMaterialReader> materials;
        ObjReadOptions options;
        options.chunks = chunks;
        if (folder) {
            materials.emplace(*folder);
            options.materials = &*materials;
            options.librariesRead = [&] {
                if (materials->refusal()) throw InputError(name + ": error: " + *materials->refusal());
            };
        }
        return readObjMesh(text, name, options);
    });
}

inline bool sameBits(double a, double b) { return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b); }
inline bool sameBits(const Vec3& a, const Vec3& b) {
    return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z);
}

// "" when the two are the same to the bit, else what differs first.
inline std::string difference(const Outcome& a, const Outcome& b) {
    if (a.mesh.has_value() != b.mesh.has_value() || a.error != b.error)
        return "outcome: '" + a.error + "' against '" + b.error + "'";
    if (!a.mesh) return "";
    const TriangleMesh &m = *a.mesh, &n = *b.mesh;
    if (m.positions.size() != n.positions.size() || m.normals.size() != n.normals.size() ||
        m.texCoords.size() != n.texCoords.size() || m.triangles.size() != n.triangles.size())
        return "sizes: " + std::to_string(m.positions.size()) + "/" + std::to_string(m.normals.size()) + "/" +
               std::to_string(m.texCoords.size()) + "/" + std::to_string(m.triangles.size()) + " against " +
               std::to_string(n.positions.size()) + "/" + std::to_string(n.normals.size()) + "/" +
               std::to_string(n.texCoords.size()) + "/" + std::to_string(n.triangles.size());
    for (size_t i = 0; i < m.positions.size(); ++i)
        if (!sameBits(m.positions[i], n.positions[i])) return "position " + std::to_string(i);
    for (size_t i = 0; i < m.normals.size(); ++i)
        if (!sameBits(m.normals[i], n.normals[i])) return "normal " + std::to_string(i);
    for (size_t i = 0; i < m.texCoords.size(); ++i)
        if (!sameBits(m.texCoords[i][0], n.texCoords[i][0]) || !sameBits(m.texCoords[i][1], n.texCoords[i][1]))
            return "texture coordinate " + std::to_string(i);
    for (size_t i = 0; i < m.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const MeshCorner &c = m.triangles[i][size_t(k)], &d = n.triangles[i][size_t(k)];
            if (c.position != d.position || c.normal != d.normal || c.texCoord != d.texCoord)
                return "triangle " + std::to_string(i);
        }
    if (!sameBits(m.boundsLo, n.boundsLo) || !sameBits(m.boundsHi, n.boundsHi)) return "bounds";
    return "";
}

}  // namespace ray::oracle
