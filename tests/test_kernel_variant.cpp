// Which kernel a device runs (host/opencl/kernel_variant.h, cl/device/variant.h) and the
// tables packed and uploaded for it: the one switch, decided from the device alone.
#include <catch2/catch.hpp>

#include "opencl/kernel_variant.h"
#include "opencl/scene_packing.h"
#include "scene/scene_loader.h"
#include "test_support.h"

using namespace ray;

namespace {

OpenClDevice cpuDevice(unsigned nativeFloatWidth) {
    OpenClDevice d;
    d.isCpu = d.isPocl = true;
    d.nativeFloatWidth = nativeFloatWidth;
    return d;
}

// Whether the variant reads the scene buffer called `name`.
bool readsBuffer(const KernelVariant& variant, const std::string& name) {
    bool reads = false, found = false;
    PackedScene().forEachBuffer([&](const auto&, SceneBufferName buffer) {
        if (buffer.name != name) return;
        found = true;
        reads = variant.reads(buffer);
    });
    REQUIRE(found);
    return reads;
}

}  // namespace

TEST_CASE("a CPU device runs packets of its native float width, or what RAY_CPU_PACKETS asks", "[opencl][variant]") {
    for (auto [width, lanes] : {std::pair{16u, 16}, {8u, 8}, {4u, 4}, {1u, 1}}) {
        INFO("native float width " << width);
        const KernelVariant v = kernelVariantFor(cpuDevice(width));
        CHECK(v.cpuThreads);
        CHECK(v.lanes == lanes);
        CHECK(v.buildDefine() == " -DRAY_CPU_LANES=" + std::to_string(lanes));
    }
    const KernelVariant oneRay = kernelVariantFor(cpuDevice(16), 1);
    CHECK(oneRay.cpuThreads);
    CHECK(oneRay.buildDefine() == " -DRAY_CPU_LANES=1");
    CHECK(kernelVariantFor(cpuDevice(16), 8).lanes == 8);
}

TEST_CASE("GPUs, llvmpipe and a device that says it is a GPU too run the GPU's kernel", "[opencl][variant]") {
    OpenClDevice gpu;
    gpu.isGpu = true;
    gpu.nativeFloatWidth = 1;
    OpenClDevice llvmpipe = cpuDevice(8);
    llvmpipe.isPocl = false;
    llvmpipe.isLlvmpipe = true;
    OpenClDevice oclgrind = cpuDevice(1);  // CL_DEVICE_TYPE_CPU | CL_DEVICE_TYPE_GPU
    oclgrind.isPocl = false;
    oclgrind.isGpu = true;
    for (const OpenClDevice& d : {gpu, llvmpipe, oclgrind}) {
        const KernelVariant v = kernelVariantFor(d, 4);  // RAY_CPU_PACKETS is a CPU device's alone
        CHECK_FALSE(v.cpuThreads);
        CHECK(v.lanes == 1);
        CHECK(v.buildDefine().empty());
    }
}

TEST_CASE("the sixteen-wide tree is packed and read only for CPU devices", "[opencl][variant]") {
    const KernelVariant gpu = kernelVariantFor(OpenClDevice{});
    const KernelVariant cpu = kernelVariantFor(cpuDevice(16));
    CHECK_FALSE(readsBuffer(gpu, "cpuNodes"));
    CHECK(readsBuffer(cpu, "cpuNodes"));
    for (const char* every : {"nodes", "primitives", "materials", "triangles"}) {
        INFO(every);
        CHECK(readsBuffer(gpu, every));
        CHECK(readsBuffer(cpu, every));
    }

    const Scene scene = loadScene(test::scenesDir() / "primitives_all.xml");
    const PackedScene forGpus = packScene(scene, {}, false), forCpus = packScene(scene, {}, true);
    CHECK(forGpus.cpuNodes.empty());
    CHECK_FALSE(forCpus.cpuNodes.empty());
    CHECK(forGpus.nodes.size() == forCpus.nodes.size());
    CHECK(forGpus.totalBytes() < forCpus.totalBytes());
}
