// libFuzzer target: Wavefront OBJ text through the mesh loader (tinyobjloader, then ray's
// triangulation, normals, texture coordinates and bounds), then the reference renderer's
// mesh BVH and a few rays through it.
//
// The text is loaded as an OBJ in a scratch folder would be, so its `mtllib` lines go
// through the confined material reader (scene/mesh.cpp, core/input_file.h): the folder
// holds a material library, a FIFO, a link to /dev/zero, a link out of the folder and a
// subfolder, named by the seeds (tests/data/fuzz/obj_loader/mtllib_*.obj). A hang (the FIFO
// opened, /dev/zero read) is libFuzzer's timeout; reading outside the folder is refused.
//
// Anything but a clean InputError is a crash. Seeds: the course's meshes and ours.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
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
