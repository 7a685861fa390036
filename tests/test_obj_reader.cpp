// The parallel OBJ reader (scene/obj_reader.h) against the tinyobjloader reading it
// replaced (tests/obj_reader_oracle.h): the same mesh to the bit, or the same error text, on
// every OBJ of the course and the project, on edge cases written here and on random text,
// whatever the number of pieces the text is cut into.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "obj_reader_oracle.h"
#include "scene/mesh.h"
#include "scene/obj_material_library.h"
#include "scene/obj_reader.h"
#include "test_support.h"

using namespace ray;
namespace fs = std::filesystem;

namespace {

oracle::Outcome newReading(const std::string& text, const std::optional<fs::path>& folder, int chunks) {
    return oracle::cutReading(text, "t.obj", folder, chunks);
}

oracle::Outcome oldReading(const std::string& text, const std::optional<fs::path>& folder) {
    return oracle::outcomeOf([&] { return oracle::parseObjMesh(text, "t.obj", folder); });
}

// Every cut from one piece to `maxChunks` gives the oracle's outcome.
void checkSameAsOracle(const std::string& text, const std::optional<fs::path>& folder, int maxChunks) {
    const oracle::Outcome expected = oldReading(text, folder);
    for (int chunks = 1; chunks <= maxChunks; ++chunks) {
        INFO("text: " << text.substr(0, 400) << "\ncut into " << chunks << " pieces");
        CHECK(oracle::difference(newReading(text, folder, chunks), expected) == "");
    }
    CHECK(oracle::difference(newReading(text, folder, 0), expected) == "");
}

std::string readText(const fs::path& file) { return test::fileText(file); }

// A folder holding materials.mtl (materials red and blue) and hostile names, as an OBJ's
// folder might; one a test case, as CTest runs the cases side by side.
fs::path materialFolder(const std::string& testCase) {
    const fs::path dir = test::freshOutputFolder("obj_reader_materials", testCase);
    fs::create_directories(dir / "sub");
    std::ofstream(dir / "materials.mtl") << "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n";
    std::ofstream(dir / "sub" / "other.mtl") << "newmtl green\nKd 0 1 0\n";
    fs::create_symlink("/dev/zero", dir / "zero.mtl");
    return dir;
}

}  // namespace

TEST_CASE("OBJ reader: the same meshes as tinyobjloader on the course's and the project's OBJ files",
          "[mesh][obj]") {
    std::vector<fs::path> files;
    for (const fs::path& dir : {test::scenesDir() / "meshes", test::testDataDir() / "meshes",
                                test::testDataDir() / "fuzz" / "obj_loader"})
        for (const auto& entry : fs::directory_iterator(dir))
            if (entry.path().extension() == ".obj") files.push_back(entry.path());
    if (auto shared = test::sharedDir()) {
        for (const auto& entry : fs::directory_iterator(*shared / "cs123" / "mesh"))
            if (entry.path().extension() == ".obj") files.push_back(entry.path());
    } else {
        test::skip("../shared/cs123 is absent: the course's meshes are not compared (the project's are)");
    }
    REQUIRE(files.size() >= 4);
    for (const fs::path& file : files) {
        INFO(file);
        const std::string text = readText(file);
        const oracle::Outcome expected = oldReading(text, file.parent_path());
        for (int chunks : {0, 1, 2, 5, 16}) {
            INFO("cut into " << chunks << " pieces");
            CHECK(oracle::difference(newReading(text, file.parent_path(), chunks), expected) == "");
        }
        // And the product's own path.
        CHECK(oracle::difference(oracle::outcomeOf([&] { return loadObjMesh(file); }),
                                 oracle::outcomeOf([&] {
                                     return oracle::parseObjMesh(text, file.string(), file.parent_path());
                                 })) == "");
    }
}

TEST_CASE("OBJ reader: edge cases read as tinyobjloader read them", "[mesh][obj]") {
    static const char kNulBytes[] = "v 0 0 0\nv 1 0 0\nv 0 1 0 \0 9\nf 1 2 3\0 0 0\nf 0\0 1 2\n";
    const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
    const std::vector<std::string> cases = {
        // Triangles, normals, texture coordinates, every corner form.
        square + "vn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 4//1\nf 1/1 2/2 4/3\n",
        // Negative indices, relative to the vertices read before the line.
        square + "vn 0 0 1\nvt 0 0\nf -4/-1/-1 -3/-1/-1 -2/-1/-1\nv 5 5 5\nf -1 -2 -3\nf -5 1 2\n",
        // Quads split along the shorter diagonal, either way.
        square + "f 1 2 3 4\nv 3 0 0\nv 3 9 0\nf 2 5 6 3\n",
        // Polygons: convex, concave, with collinear corners (tinyobjloader's ear clipping).
        "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 2 2 0\nv 0 2 0\nv -1 1 0\nf 1 2 3 4 5 6\n",
        "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 2 1 0\nv 0 4 0\nf 1 2 3 4 5\n",
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 3 1 0\nf 1 2 3 4 5\n",
        "v 0 0 0\nv 0 1 0\nv 0 1 1\nv 0 0.5 2\nv 0 0 1\nf 1 2 3 4 5\nv 1 0 0\nv 1 1 1\nf 6 7 1 2 3 4 5\n",
        // Polygons naming vertices read after them: triangulated over those read when their
        // group closes (g, o, a usemtl that changes the material, the end).
        "v 0 0 0\nf 1 2 3 4\nv 1 0 0\nv 1 1 0\nv 0 1 0\n",
        "v 0 0 0\nf 1 2 3 4\ng next\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\n",
        "v 0 0 0\nv 1 0 0\nf 1 2 3 4 5\no next\nv 1 1 0\nv 0 1 0\nv 0 2 0\nf 1 2 3\n",
        "v 0 0 0\nf 1 2 3 4\nusemtl red\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\n",
        "mtllib materials.mtl\nv 0 0 0\nf 1 2 3 4\nusemtl red\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\n",
        "mtllib materials.mtl\nusemtl red\nv 0 0 0\nf 1 2 3 4\nusemtl red\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 4 3\n",
        "mtllib missing.mtl sub/other.mtl\nv 0 0 0\nf 1 2 3 4\nusemtl green\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\n",
        "mtllib a\\ b.mtl  materials.mtl\nv 0 0 0\nf 1 2 3 4\nusemtl blue\nv 1 0 0\nv 1 1 0\nv 0 1 0\n",
        // Faces of fewer than three corners are dropped; one naming a missing vertex is an error.
        square + "f 1 2\nf\nf 1 2 3\n",
        square + "f 1 2 9\n",
        square + "f 1 2 3 9\nf 1 2 3\n",
        square + "f 1 2 -9\n",
        square + "vn 0 0 1\nvt 0 0\nf 1/5/7 2/-3/-2 3/1/1\n",
        // Unreadable lines: tinyobjloader's message with the line's number.
        square + "\n\n# comment\nf 0 1 2\n",
        square + "f 1/ 2 3\n",
        square + "f 1/ 2/3 4\n",
        square + "f 1// 2 3\n",
        square + "l 1 0\nf 1 2 3\n",
        square + "p  0\nf 1 2 3\n",
        square + "l 1 2 3\np 1\nf 1 2 3\n",
        square + "vw 0 1 0.5 2 0.5\nvw 1 -1 0.5\nf 1 2 3\n",
        square + "vw 0 x 0.5\nf 1 2 3\n",
        square + "vw 3\nf 1 2 3\nvw 0 0 1 abc\n",
        "mtllib ../outside.mtl\nv 0 0 0\nf 0 1 2\n",
        "mtllib zero.mtl\n" + square + "f 1 2 3\n",
        "v 0 0 0\nf 0 1 2\nmtllib zero.mtl\n",
        // Line ends: CR LF, CR alone, none at the end; NUL bytes; blanks and tabs.
        "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\nf 0 0 0\r\n",
        "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\rf 1 0 2\r",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3",
        std::string(kNulBytes, sizeof kNulBytes - 1),
        "\t v\t0 0 0\n  v 1\t0 0\nv 0  1 0\n\tf\t1  2\t 3 \t\n",
        // Numbers as tinyobjloader parses them: exponents, leading dots, long fractions,
        // garbage after the digits, missing coordinates.
        "v 1e2 -2.5E-3 +.5\nv -.25e+1 0.12345678901234 1,5\nv 7\nv 1e400 -1e-400 0e999\nf 1 2 3\nf 2 3 4\n",
        "v 1e 2 3\nv . - +\nv 1.5e+ 2. 3.e1\nf 1 2 3\n",
        "vn 1 2\nvt 0.5\nvt 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/1 2/1/1 3/2/1\n",
        // Indices beyond int, and atoi's white space.
        square + "f 1 2 99999999999\n",
        square + "f 1 2 -99999999999999999999\n",
        square + "f 1 2 4294967297\n",
        square + "f 1 2 20000000000000000000\n",
        square + "f 1 2 -20000000000000000000 3\n",
        square + "f 1 2 9223372036854775807\nf 1 2 9223372036854775808\nf 1 2 -9223372036854775808\n",
        square + "f 1 2 -9223372036854775809\nf 1 2 18446744073709551617\n",
        square + "f 1 2 9223372036854775800\nf 3 2 -9223372036854775800\nf 1 2 922337203685477581\n",
        square + "f 1/\v2 2 3\n",
        // No faces: an error.
        "",
        "v 0 0 0\n",
        "# nothing\n\n",
        // Lines and directives a mesh ignores.
        square + "s 1\ns off\nt crease 2/1/0 1 2 0.5\no name with spaces\ng a b\nusemtl\nf 1 2 3\n",
        square + "usemtlred\nmtllib\nmtllibx y\nvp 1 2\nf 1 2 3\n",
    };
    const fs::path folder = materialFolder("edge_cases");
    for (const std::string& text : cases) {
        checkSameAsOracle(text, folder, 6);
        checkSameAsOracle(text, std::nullopt, 3);
    }
}

// Random lines from the OBJ directives (well and badly formed), many texts, many cuts.
TEST_CASE("OBJ reader: random OBJ text reads as tinyobjloader read it", "[mesh][obj]") {
    std::mt19937 random(51);
    auto pick = [&](int n) { return int(random() % unsigned(n)); };
    auto number = [&]() -> std::string {
        static const char* const odd[] = {"1e3", "-.5", "+2.", "1e-2", "0.123456789", "x", "", "1e", "-0", "3,5"};
        if (pick(8) == 0) return odd[pick(10)];
        return std::to_string(pick(2001) - 1000) + "." + std::to_string(pick(1000));
    };
    auto index = [&]() -> std::string {
        int r = pick(20);
        if (r == 0) return "0";
        if (r < 5) return std::to_string(-1 - pick(8));
        return std::to_string(1 + pick(12));
    };
    auto corner = [&]() -> std::string {
        switch (pick(5)) {
            case 0: return index();
            case 1: return index() + "/" + index();
            case 2: return index() + "//" + index();
            case 3: return index() + "/" + index() + "/" + index();
            default: return index() + (pick(10) == 0 ? "/" : "");
        }
    };
    const char* const endings[] = {"\n", "\n", "\n", "\r\n", "\r", " \n", "\t\n"};
    const fs::path folder = materialFolder("random");
    for (int t = 0; t < 300; ++t) {
        std::string text;
        const int lines = 1 + pick(40);
        for (int l = 0; l < lines; ++l) {
            int kind = pick(20);
            if (kind < 6) {
                text += "v " + number() + " " + number() + " " + number();
            } else if (kind < 8) {
                text += "vn " + number() + " " + number() + " " + number();
            } else if (kind < 10) {
                text += "vt " + number() + " " + number();
            } else if (kind < 16) {
                text += "f";
                const int corners = pick(10) == 0 ? pick(3) : 3 + pick(pick(3) == 0 ? 5 : 2);
                for (int c = 0; c < corners; ++c) {
                    text += ' ';
                    text += corner();
                }
            } else if (kind == 16) {
                static const char* const groups[] = {"g a", "o b", "usemtl red", "usemtl blue", "usemtl x", "s 1"};
                text += groups[pick(6)];
            } else if (kind == 17) {
                text += pick(4) == 0 ? "mtllib materials.mtl" : "# comment";
            } else if (kind == 18) {
                text += pick(2) ? "l " : "p ";
                text += corner();
                text += ' ';
                text += corner();
            } else {
                text += pick(2) ? "" : "vw 0 " + number() + " 1";
            }
            text += endings[pick(7)];
        }
        checkSameAsOracle(text, folder, 4);
    }
}

TEST_CASE("OBJ reader: a large text cut into many pieces keeps every line's number", "[mesh][obj]") {
    std::string text;
    const int side = 60;
    for (int j = 0; j <= side; ++j)
        for (int i = 0; i <= side; ++i) text += "v " + std::to_string(i) + " " + std::to_string(j) + " 0.5\n";
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
            int p = j * (side + 1) + i + 1;
            text += "f " + std::to_string(p) + " " + std::to_string(p + 1) + " " + std::to_string(p + side + 2) +
                    "\nf -1 -2 -" + std::to_string(side + 2) + "\n";
        }
    checkSameAsOracle(text, std::nullopt, 9);
    const std::string broken = text + "f 1 2 0\n" + text;
    checkSameAsOracle(broken, std::nullopt, 9);
    const oracle::Outcome outcome = newReading(broken, std::nullopt, 7);
    CHECK(outcome.error.find("t.obj:" + std::to_string((side + 1) * (side + 1) + 2 * side * side + 1) +
                             ": error: cannot read the OBJ file") == 0);
}
