#include "mesh_scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace bench {

namespace fs = std::filesystem;

namespace {

// A camera, one light and the mesh inside `transform` (a <transblock>'s contents before
// the object). The mesh is gray and slightly reflective, so depth 4 spawns secondary rays.
void writeScene(const fs::path& sceneFile, const std::string& objName, const std::string& transform) {
    std::ofstream out(sceneFile);
    out << "<scenefile>\n"
           "  <globaldata><ambientcoeff v=\"0.5\"/><diffusecoeff v=\"0.5\"/><specularcoeff v=\"0.5\"/></globaldata>\n"
           "  <cameradata><pos x=\"0\" y=\"0.3\" z=\"2.2\"/><focus x=\"0\" y=\"0\" z=\"0\"/>"
           "<up x=\"0\" y=\"1\" z=\"0\"/><heightangle v=\"40\"/></cameradata>\n"
           "  <lightdata><id v=\"0\"/><type v=\"point\"/><color r=\"1\" g=\"1\" b=\"1\"/>"
           "<position x=\"2\" y=\"3\" z=\"4\"/><function v1=\"1\" v2=\"0\" v3=\"0\"/></lightdata>\n"
           "  <object type=\"tree\" name=\"root\">\n"
           "    <transblock>\n"
        << transform
        << "      <object type=\"primitive\" name=\"mesh\" filename=\"" << objName << "\">\n"
           "        <diffuse r=\"0.7\" g=\"0.7\" b=\"0.75\"/><ambient r=\"0.1\" g=\"0.1\" b=\"0.1\"/>\n"
           "        <specular r=\"0.5\" g=\"0.5\" b=\"0.5\"/><shininess v=\"30\"/>"
           "<reflective r=\"0.2\" g=\"0.2\" b=\"0.2\"/>\n"
           "      </object>\n"
           "    </transblock>\n"
           "  </object>\n"
           "</scenefile>\n";
    if (!out) throw std::runtime_error(sceneFile.string() + ": cannot write");
}

}  // namespace

uint64_t writeUvSphereScene(const fs::path& sceneFile, const fs::path& objFile, uint64_t triangles) {
    const int rings = std::max(3, int(std::lround(std::sqrt(double(triangles) / 4.0))));
    const int segments = 2 * rings;
    std::ofstream out(objFile);
    out.setf(std::ios::fixed);
    out.precision(6);
    // Vertices: the two poles, then (rings − 1) latitude circles of `segments` each.
    auto vertex = [&](double theta, double phi) {
        double x = std::sin(theta) * std::cos(phi), y = std::cos(theta), z = std::sin(theta) * std::sin(phi);
        out << "v " << 0.5 * x << ' ' << 0.5 * y << ' ' << 0.5 * z << "\nvn " << x << ' ' << y << ' ' << z << '\n';
    };
    vertex(0, 0);
    vertex(std::numbers::pi, 0);
    for (int r = 1; r < rings; ++r)
        for (int s = 0; s < segments; ++s)
            vertex(std::numbers::pi * r / rings, 2 * std::numbers::pi * s / segments);
    // OBJ indices are 1-based: 1 north pole, 2 south pole, 3.. the circles.
    auto at = [&](int ring, int s) { return 3 + (ring - 1) * segments + (s % segments); };
    auto face = [&](int a, int b, int c) {
        out << "f " << a << "//" << a << ' ' << b << "//" << b << ' ' << c << "//" << c << '\n';
    };
    uint64_t count = 0;
    for (int s = 0; s < segments; ++s) {
        face(1, at(1, s + 1), at(1, s));  // counter-clockwise seen from outside
        face(2, at(rings - 1, s), at(rings - 1, s + 1));
        count += 2;
        for (int r = 1; r + 1 < rings; ++r) {
            face(at(r, s), at(r, s + 1), at(r + 1, s + 1));
            face(at(r, s), at(r + 1, s + 1), at(r + 1, s));
            count += 2;
        }
    }
    if (!out) throw std::runtime_error(objFile.string() + ": cannot write");
    writeScene(sceneFile, objFile.filename().string(), "");
    return count;
}

void writeSingleMeshScene(const fs::path& sceneFile, const fs::path& objFile) {
    std::ifstream in(objFile);
    double lo[3], hi[3];
    std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
    std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
    std::string line;
    while (std::getline(in, line)) {
        if (line.size() < 2 || line[0] != 'v' || line[1] != ' ') continue;
        double p[3];
        if (std::sscanf(line.c_str() + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) != 3) continue;
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    }
    if (!(lo[0] <= hi[0])) throw std::runtime_error(objFile.string() + ": no vertices");
    double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-12});
    std::string transform = "      <scale x=\"" + std::to_string(1.2 / size) + "\" y=\"" + std::to_string(1.2 / size) +
                            "\" z=\"" + std::to_string(1.2 / size) + "\"/>\n" + "      <translate x=\"" +
                            std::to_string(-(lo[0] + hi[0]) / 2) + "\" y=\"" + std::to_string(-(lo[1] + hi[1]) / 2) +
                            "\" z=\"" + std::to_string(-(lo[2] + hi[2]) / 2) + "\"/>\n";
    writeScene(sceneFile, objFile.string(), transform);
}

}  // namespace bench
