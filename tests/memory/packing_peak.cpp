// What packing a large mesh holds at its peak (issue 51: "nothing of a mesh kept twice once
// it is packed"). Its own program, because it counts every block operator new hands out,
// on every thread: the packing's peak over the bytes the packing it returns keeps.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>

#include <malloc.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>

#include "opencl/scene_packing.h"
#include "scene/scene_loader.h"

namespace {

std::atomic<size_t> liveBytes{0};
std::atomic<size_t> peakBytes{0};

void* counted(void* block) {
    if (!block) throw std::bad_alloc();
    const size_t live = liveBytes += malloc_usable_size(block);
    size_t peak = peakBytes.load();
    while (live > peak && !peakBytes.compare_exchange_weak(peak, live)) {
    }
    return block;
}

void uncounted(void* block) {
    if (!block) return;
    liveBytes -= malloc_usable_size(block);
    std::free(block);
}

void* alignedBlock(size_t bytes, std::align_val_t alignment) {
    const size_t a = std::max(size_t(alignment), sizeof(void*));
    return std::aligned_alloc(a, (std::max<size_t>(bytes, 1) + a - 1) / a * a);
}

}  // namespace

void* operator new(size_t bytes) { return counted(std::malloc(std::max<size_t>(bytes, 1))); }
void* operator new[](size_t bytes) { return counted(std::malloc(std::max<size_t>(bytes, 1))); }
void* operator new(size_t bytes, std::align_val_t a) { return counted(alignedBlock(bytes, a)); }
void* operator new[](size_t bytes, std::align_val_t a) { return counted(alignedBlock(bytes, a)); }
void operator delete(void* block) noexcept { uncounted(block); }
void operator delete[](void* block) noexcept { uncounted(block); }
void operator delete(void* block, size_t) noexcept { uncounted(block); }
void operator delete[](void* block, size_t) noexcept { uncounted(block); }
void operator delete(void* block, std::align_val_t) noexcept { uncounted(block); }
void operator delete[](void* block, std::align_val_t) noexcept { uncounted(block); }
void operator delete(void* block, size_t, std::align_val_t) noexcept { uncounted(block); }
void operator delete[](void* block, size_t, std::align_val_t) noexcept { uncounted(block); }

namespace {

// A wavy grid of n x n cells, two triangles a cell (../shared/embree/mesh_scenes.py's
// surface), as an OBJ file and a scene that places it once.
std::filesystem::path writeGridScene(int n) {
    const std::filesystem::path folder = std::filesystem::path(RAY_TEST_OUTPUT_DIR) / "packing_peak";
    std::filesystem::create_directories(folder);
    std::ofstream obj(folder / "grid.obj");
    char line[96];
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = double(i) / n * 2 - 1, y = double(j) / n * 2 - 1;
            std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", x, y, 0.1 * std::sin(8 * x) * std::cos(8 * y));
            obj << line;
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int p = j * (n + 1) + i + 1;
            obj << "f " << p << ' ' << p + 1 << ' ' << p + n + 2 << "\nf " << p << ' ' << p + n + 2 << ' ' << p + n + 1
                << '\n';
        }
    std::ofstream(folder / "grid.xml")
        << "<scenefile><cameradata><pos x=\"0\" y=\"-2\" z=\"2\"/><look x=\"0\" y=\"2\" z=\"-2\"/>"
           "<up x=\"0\" y=\"0\" z=\"1\"/><heightangle v=\"45\"/></cameradata>"
           "<object type=\"tree\" name=\"root\"><transblock><object type=\"primitive\" name=\"mesh\" "
           "meshfile=\"grid.obj\"><diffuse r=\"1\" g=\"1\" b=\"1\"/></object></transblock></object></scenefile>\n";
    return folder / "grid.xml";
}

// The bytes a packing keeps: its tables' and its own arrays' blocks.
size_t keptBytes(const ray::PackedScene& packed) {
    size_t bytes = 0;
    packed.forEachBuffer([&](const auto& table, ray::SceneBufferName) { bytes += table.capacity() * sizeof(table[0]); });
    return bytes + packed.primitiveOrder.capacity() * sizeof(uint32_t) + packed.meshRoots.capacity() * sizeof(int);
}

}  // namespace

TEST_CASE("packing a mesh holds little more at its peak than the tables it keeps", "[packed][memory]") {
    // 180,000 triangles: above the packing's threshold for running on every core.
    const ray::Scene scene = ray::loadScene(writeGridScene(300));
    REQUIRE(scene.meshes.size() == 1);
    REQUIRE(scene.meshes[0].triangles.size() == 180000);
    const size_t before = liveBytes.load();
    peakBytes = before;
    const ray::PackedScene packed = ray::packScene(scene);
    const size_t peak = peakBytes.load() - before, kept = keptBytes(packed);
    INFO("packing peak " << peak << " bytes, kept " << kept << " (" << double(peak) / double(kept) << "x)");
    // The tables are written last, each once; before them only what they are built from
    // (the boxes, the trees), which is smaller. Above the tables at the peak: the mesh's
    // triangle order (4 bytes a triangle, 2.5% of the 160 kept) and the threads' small blocks.
    CHECK(peak <= kept + kept / 20);
}
