// Mesh scenes for the bench: generated UV spheres of 10^3..10^6 triangles (the scaling
// row) and a one-mesh scene around any OBJ file (the course's xyzrgb_dragon.obj, which no
// course scene uses).
#pragma once

#include <cstdint>
#include <filesystem>

namespace bench {

// Writes a UV sphere of about `triangles` triangles (2·segments·(rings − 1) with
// segments = 2·rings; smooth vn, no vt) to objFile, and a scene showing it to sceneFile
// (the OBJ named relative to the scene). Returns the exact triangle count.
uint64_t writeUvSphereScene(const std::filesystem::path& sceneFile, const std::filesystem::path& objFile,
                            uint64_t triangles);

// Writes a scene that shows the OBJ file (an absolute path) scaled into a unit box in front
// of the camera. Throws std::runtime_error when the file holds no vertices.
void writeSingleMeshScene(const std::filesystem::path& sceneFile, const std::filesystem::path& objFile);

}  // namespace bench
