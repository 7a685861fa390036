// Wavefront OBJ text read in parallel: the text is cut into chunks at line ends, each chunk
// parsed on its own thread into flat arrays (no allocation a line), then the chunks are
// joined (a negative index counts back from the vertices read before its line, so it is
// resolved once the counts of the chunks before it are known).
//
// What it makes of a file is what tinyobjloader 2.0.0rc10 (Debian 12's, the reader used
// before; float, triangulating) made of it, to the bit: its number parsing, its index rules,
// its triangulation of quads (the shorter diagonal) and of larger polygons (its ear clipping,
// over the vertices read by the polygon's next g, o or usemtl line), its mtllib and usemtl
// handling, and the text of its errors (it stops at the first line it cannot read). Only
// what a mesh keeps is made: positions, normals, texture coordinates and triangles. The
// differential tests (tests/test_obj_reader.cpp) and fuzz/fuzz_obj_loader hold it to that.
#pragma once

#include <functional>
#include <string>
#include <string_view>

#include "scene/mesh.h"

namespace tinyobj {
class MaterialReader;
}

namespace ray {

struct ObjReadOptions {
    // Reads each mtllib line's libraries in turn, as tinyobjloader asks its MaterialReader
    // (their material names decide which usemtl lines close a group); nullptr: mtllib lines
    // are passed over.
    tinyobj::MaterialReader* materials = nullptr;
    // Called once the mtllib lines before the first unreadable line are read, before any
    // fault of the text is reported: a library the caller refused is reported first.
    std::function<void()> librariesRead;
    // How many pieces the text is cut into; 0: one a core for a large text, one for a small
    // one. Every count gives the same mesh (the tests cut small texts into many pieces).
    int chunks = 0;
};

// The OBJ's mesh (mesh.h: vertices as given, polygons triangulated). InputError for a line
// that cannot be read ("name:line: error: cannot read the OBJ file: ..."), a face naming a
// vertex that does not exist, or a text without faces.
TriangleMesh readObjMesh(std::string_view text, const std::string& nameForErrors, const ObjReadOptions& options = {});

}  // namespace ray
