// libFuzzer target: Wavefront OBJ text through the mesh loader (scene/obj_reader.h: the text
// parsed in pieces on several threads, polygons triangulated, normals, texture coordinates
// and bounds), then the reference renderer's mesh BVH and a few rays through it.
//
// Differential: the reader must make what tinyobjloader made of the text (the reading it
// replaced, tests/obj_reader_oracle.h), the same mesh to the bit or the same error text,
// read whole and cut into three pieces; a difference is a crash.
//
// The text is loaded as an OBJ in a scratch folder would be, so its `mtllib` lines go
// through the confined material reader (scene/obj_material_library.h, core/input_file.h): the folder
// holds a material library, a FIFO, a link to /dev/zero, a link out of the folder and a
// subfolder, named by the seeds (tests/data/fuzz/obj_loader/mtllib_*.obj). A hang (the FIFO
// opened, /dev/zero read) is libFuzzer's timeout; reading outside the folder is refused.
//
// Anything but a clean InputError is a crash. Seeds: the course's meshes and ours.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "../tests/obj_reader_oracle.h"
#include "scene/mesh.h"
#include "reference/mesh_intersector.h"
#include "scene/scene.h"

namespace {

// The folder the fuzzed OBJ is "in", made once a process.
std::filesystem::path scratchFolder() {
    static const std::filesystem::path folder = [] {
        static char pattern[] = "/tmp/ray_fuzz_obj_XXXXXX";  // no destructor: read at exit
        const char* made = ::mkdtemp(pattern);
        if (!made) std::abort();
        const std::filesystem::path dir = made;
        std::ofstream(dir / "good.mtl") << "newmtl red\nKd 1 0 0\nmap_Kd ../../etc/passwd\n";
        ::mkfifo((dir / "fifo.mtl").c_str(), 0600);
        std::filesystem::create_symlink("/dev/zero", dir / "zero.mtl");
        std::filesystem::create_symlink("/etc/hostname", dir / "out.mtl");
        std::filesystem::create_directories(dir / "sub");
        std::ofstream(dir / "sub" / "inner.mtl") << "newmtl blue\nKd 0 0 1\n";
        std::atexit([] {
            std::error_code ignored;
            std::filesystem::remove_all(pattern, ignored);
        });
        return dir;
    }();
    return folder;
}

// Aborts (a crash for libFuzzer) where the reader and tinyobjloader disagree.
void checkAgainstTinyobjloader(const std::string& text) {
    namespace oracle = ray::oracle;
    const oracle::Outcome expected =
        oracle::outcomeOf([&] { return oracle::parseObjMesh(text, "fuzzed.obj", scratchFolder()); });
    for (int chunks : {0, 3}) {
        const std::string difference =
            oracle::difference(oracle::cutReading(text, "fuzzed.obj", scratchFolder(), chunks), expected);
        if (difference.empty()) continue;
        std::fprintf(stderr, "the OBJ reader (%d pieces) differs from tinyobjloader: %s\n", chunks, difference.c_str());
        std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    checkAgainstTinyobjloader(text);
    try {
        ray::TriangleMesh mesh = ray::parseObjMesh(text, "fuzzed.obj", scratchFolder());
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
