#include <catch2/catch.hpp>

#include <memory>

#include "kernel_comparison.h"
#include "opencl/device_slot.h"
#include "opencl/scene_upload.h"
#include "scene/scene_difference.h"

namespace {

using namespace ray;
using namespace ray::engine;

// A slot of `device` with its context open, as the engine's device thread opens it.
std::shared_ptr<DeviceSlot> openSlot(const OpenClDevice& device, bool copyScene) {
    auto slot = std::make_shared<DeviceSlot>();
    slot->device = device;
    slot->hooks.copyScene = copyScene;
    slot->variant = kernelVariantFor(device);
    slot->context = cl::Context(device.device);
    return slot;
}

// A packing and the one after a material edit, with their tables' versions as
// PackedSceneCache gives them: the materials new, every other table the same.
std::pair<std::shared_ptr<PackedScene>, std::shared_ptr<PackedScene>> packingAndItsEdit() {
    const Scene scene = loadScene(test::scenesDir() / "shadows.xml");
    Scene recolored = scene;
    recolored.materials[1].diffuse = {1, 0, 0};
    auto before = std::make_shared<PackedScene>(packScene(scene));
    auto after = std::make_shared<PackedScene>(*repackScene(*before, recolored, {}, compareScenes(scene, recolored)));
    uint64_t version = 0;
    for (uint64_t& v : before->versions) v = ++version;
    size_t i = 0;
    before->forEachBuffer([&](const auto&, SceneBufferName name) {
        after->versions[i] = std::string(name.name) == "materials" ? ++version : before->versions[i];
        ++i;
    });
    return {before, after};
}

}  // namespace

TEST_CASE("after an edit a device holds the new packing alone, not the old one beside it", "[upload][edit]") {
    const auto device = test::cpuDevice();
    if (!device) return test::skip("no OpenCL CPU device");
    for (const bool copyScene : {false, true}) {
        INFO((copyScene ? "the tables copied into the device's buffers" : "the tables read in place"));
        const auto slot = openSlot(*device, copyScene);
        auto [before, after] = packingAndItsEdit();
        CHECK(uploadScene(*slot, before));
        CHECK(uploadScene(*slot, after));  // the materials
        const std::weak_ptr<const PackedScene> old = before;
        before.reset();
        // The engine's cache has let go of the old packing: nothing else keeps it.
        CHECK(old.expired());
        for (const cl::Buffer& buffer : slot->sceneBuffers) CHECK(buffer());
        // Nothing new to upload for the same packing.
        CHECK_FALSE(uploadScene(*slot, after));
    }
}
