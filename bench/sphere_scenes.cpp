#include "sphere_scenes.h"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace bench {

namespace {

constexpr int kChildrenPerLevel = 10;
constexpr uint32_t kBaseSeed = 20240123;

// std::mt19937's sequence is fixed by the standard, but the std:: distributions are not;
// drawing the doubles ourselves keeps the scenes byte-identical on every standard library.
class DeterministicRandom {
public:
    explicit DeterministicRandom(uint32_t seed) : engine_(seed) {}
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(engine_() >> 8) * 0x1p-24; }

private:
    std::mt19937 engine_;
};

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.5f", v);
    return text;
}

std::string xyz(double x, double y, double z) {
    return "x=\"" + number(x) + "\" y=\"" + number(y) + "\" z=\"" + number(z) + "\"";
}

std::string rgb(double r, double g, double b) {
    return "r=\"" + number(r) + "\" g=\"" + number(g) + "\" b=\"" + number(b) + "\"";
}

// A random offset that keeps a box of side `size` inside the unit box.
double offsetInsideUnitBox(DeterministicRandom& random, double size) {
    double room = 0.5 - size / 2;
    return random.uniform(-room, room);
}

// Every other sphere is a mirror-ish one, so that depth 4 has secondary rays to trace.
void writeSphereMaterial(std::ostream& out, DeterministicRandom& random, bool reflective) {
    double r = random.uniform(0.2, 0.9), g = random.uniform(0.2, 0.9), b = random.uniform(0.2, 0.9);
    out << "        <object type=\"primitive\" name=\"sphere\">\n"
        << "          <diffuse " << rgb(r, g, b) << "/>\n"
        << "          <ambient " << rgb(0.1 * r, 0.1 * g, 0.1 * b) << "/>\n"
        << "          <specular " << rgb(0.6, 0.6, 0.6) << "/>\n"
        << "          <shininess v=\"" << number(random.uniform(15, 60)) << "\"/>\n";
    if (reflective) out << "          <reflective " << rgb(0.4, 0.4, 0.4) << "/>\n";
    out << "        </object>\n";
}

// L1: ten spheres of random diameter at random places inside the unit box.
void writeLeafLevel(std::ostream& out) {
    DeterministicRandom random(kBaseSeed + 1);
    out << "  <object type=\"tree\" name=\"L1\">\n";
    for (int i = 0; i < kChildrenPerLevel; ++i) {
        double diameter = random.uniform(0.15, 0.4);
        double x = offsetInsideUnitBox(random, diameter), y = offsetInsideUnitBox(random, diameter),
               z = offsetInsideUnitBox(random, diameter);
        out << "    <transblock>\n"
            << "      <translate " << xyz(x, y, z) << "/>\n"
            << "      <scale " << xyz(diameter, diameter, diameter) << "/>\n";
        writeSphereMaterial(out, random, i % 2 == 0);
        out << "    </transblock>\n";
    }
    out << "  </object>\n";
}

// Lk: ten copies of L(k-1), each about half the size, at random places in the unit box.
// Half-size copies overlap a little, which keeps the image about as covered at every level.
void writeInnerLevel(std::ostream& out, int level) {
    DeterministicRandom random(kBaseSeed + uint32_t(level));
    out << "  <object type=\"tree\" name=\"L" << level << "\">\n";
    for (int i = 0; i < kChildrenPerLevel; ++i) {
        double size = random.uniform(0.4, 0.55);
        double x = offsetInsideUnitBox(random, size), y = offsetInsideUnitBox(random, size),
               z = offsetInsideUnitBox(random, size);
        out << "    <transblock>\n"
            << "      <translate " << xyz(x, y, z) << "/>\n"
            << "      <scale " << xyz(size, size, size) << "/>\n"
            << "      <object type=\"master\" name=\"L" << (level - 1) << "\"/>\n"
            << "    </transblock>\n";
    }
    out << "  </object>\n";
}

// The camera sees the whole 10-unit box standing on the floor, from above and to the side.
void writeCameraAndLights(std::ostream& out) {
    out << "  <globaldata>\n"
        << "    <ambientcoeff v=\"0.5\"/>\n    <diffusecoeff v=\"0.5\"/>\n"
        << "    <specularcoeff v=\"0.5\"/>\n    <transparentcoeff v=\"0.5\"/>\n"
        << "  </globaldata>\n"
        << "  <cameradata>\n"
        << "    <pos " << xyz(9, 8.5, 11.5) << "/>\n"
        << "    <focus " << xyz(0, 5, 0) << "/>\n"
        << "    <up " << xyz(0, 1, 0) << "/>\n"
        << "    <heightangle v=\"45\"/>\n"
        << "  </cameradata>\n"
        << "  <lightdata>\n"
        << "    <id v=\"0\"/>\n    <type v=\"point\"/>\n"
        << "    <color " << rgb(1, 1, 1) << "/>\n"
        << "    <position " << xyz(-8, 20, 12) << "/>\n"
        << "    <function v1=\"1\" v2=\"0\" v3=\"0\"/>\n"
        << "  </lightdata>\n"
        << "  <lightdata>\n"
        << "    <id v=\"1\"/>\n    <type v=\"directional\"/>\n"
        << "    <color " << rgb(0.5, 0.5, 0.45) << "/>\n"
        << "    <direction " << xyz(-0.5, -1, -0.3) << "/>\n"
        << "  </lightdata>\n";
}

void writeRoot(std::ostream& out, int levels) {
    out << "  <object type=\"tree\" name=\"root\">\n"
        << "    <transblock>\n"
        << "      <translate " << xyz(0, -0.25, 0) << "/>\n"
        << "      <scale " << xyz(60, 0.5, 60) << "/>\n"
        << "      <object type=\"primitive\" name=\"cube\">\n"
        << "        <diffuse " << rgb(0.7, 0.7, 0.72) << "/>\n"
        << "        <ambient " << rgb(0.08, 0.08, 0.08) << "/>\n"
        << "      </object>\n"
        << "    </transblock>\n"
        << "    <transblock>\n"
        << "      <translate " << xyz(0, 5, 0) << "/>\n"
        << "      <scale " << xyz(10, 10, 10) << "/>\n"
        << "      <object type=\"master\" name=\"L" << levels << "\"/>\n"
        << "    </transblock>\n"
        << "  </object>\n";
}

}  // namespace

void writeSphereScene(const std::filesystem::path& file, int levels) {
    if (levels < 1) throw std::invalid_argument("a sphere scene needs at least one level");
    std::ostringstream out;
    out << "<!-- ray_bench: 10^" << levels << " spheres in " << levels << " levels of masters -->\n"
        << "<scenefile>\n";
    writeCameraAndLights(out);
    writeLeafLevel(out);
    for (int level = 2; level <= levels; ++level) writeInnerLevel(out, level);
    writeRoot(out, levels);
    out << "</scenefile>\n";

    std::ofstream stream(file);
    stream << out.str();
    if (!stream) throw std::runtime_error(file.string() + ": cannot write the scene");
}

}  // namespace bench
