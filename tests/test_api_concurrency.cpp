// The public API's thread-safety guarantee (include/ray/renderer.h): Renderers, each used
// by one thread, render at once on several threads exactly what they render one at a time.
#include <catch2/catch.hpp>

#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "ray/ray.h"
#include "test_support.h"

namespace {

namespace api = ray::api;

bool haveCpu() {
    for (const api::Device& device : api::listDevices())
        if (device.cpu) return true;
    return false;
}

// One Renderer's work: `frames` frames of a camera moving along x, each frame's pixels.
struct Job {
    const api::Scene& scene;  // shared by the threads: each Renderer copies it
    std::string devices;
    std::vector<std::vector<float>> frames;
};

void runJob(Job& job, int frames) {
    const api::Scene& scene = job.scene;
    api::Renderer renderer(scene, job.devices);
    api::Settings settings;
    settings.width = 96;
    settings.height = 72;
    renderer.setSettings(settings);
    api::Camera camera = scene.camera();
    job.frames.clear();
    for (int frame = 0; frame < frames; ++frame) {
        camera.position.x += 0.2;
        renderer.setCamera(camera);
        job.frames.push_back(renderer.render());
    }
}

}  // namespace

TEST_CASE("API: two Renderers on two threads at once render what they render one at a time",
          "[api][kernel][concurrency]") {
    for (const std::string devices : {"cpu", "ref"}) {
        DYNAMIC_SECTION(devices) {
            if (devices == "cpu" && !haveCpu()) {
                ray::test::skip("no OpenCL CPU device");
                return;
            }
            // Two scenes (cross-talk between the Renderers would show), then one Scene object
            // for both (each Renderer copies it; they share every cache entry).
            const api::Scene primitives = api::Scene::load(ray::test::scenesDir() / "primitives_all.xml").scene;
            const api::Scene showpiece = api::Scene::load(ray::test::scenesDir() / "showpiece.xml").scene;
            for (const auto& [first, second] : {std::pair{&primitives, &showpiece}, std::pair{&showpiece, &showpiece}}) {
                constexpr int kFrames = 3;
                Job aloneA{*first, devices, {}}, aloneB{*second, devices, {}};
                runJob(aloneA, kFrames);
                runJob(aloneB, kFrames);
                Job a{*first, devices, {}}, b{*second, devices, {}};
                std::exception_ptr otherFailed;
                std::thread other([&] {
                    try {
                        runJob(b, kFrames);
                    } catch (...) {
                        otherFailed = std::current_exception();
                    }
                });
                runJob(a, kFrames);
                other.join();
                if (otherFailed) std::rethrow_exception(otherFailed);
                INFO(devices << (first == second ? ": one scene on both threads" : ": two scenes"));
                REQUIRE(a.frames.size() == size_t(kFrames));
                REQUIRE(b.frames.size() == size_t(kFrames));
                for (int f = 0; f < kFrames; ++f) {
                    CHECK(a.frames[size_t(f)] == aloneA.frames[size_t(f)]);
                    CHECK(b.frames[size_t(f)] == aloneB.frames[size_t(f)]);
                }
            }
        }
    }
}
