// Soak of the public API (issue 26): one Renderer through 500 frames of a moving camera.
// Resident memory, open descriptors and threads stay flat after a warm-up (the bounds are
// below, and the figures are printed), and sampled frames equal fresh renders of their camera.
// The viewer and MPI soaks: tests/soak.py.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "ray/ray.h"
#include "test_support.h"

namespace {

namespace api = ray::api;
namespace fs = std::filesystem;

struct Resources {
    long rssKiB = 0;
    long descriptors = 0;
    long threads = 0;
};

long statusField(const std::string& name) {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind(name + ":", 0) == 0) return std::stol(line.substr(name.size() + 1));
    return -1;
}

Resources measure() {
    Resources r;
    r.rssKiB = statusField("VmRSS");
    r.threads = statusField("Threads");
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator("/proc/self/fd")) ++r.descriptors;
    return r;
}

// The camera of frame `frame`: once around the scene in 500 frames, bobbing up and down.
api::Camera cameraAt(const api::Camera& start, int frame) {
    api::Camera camera = start;
    const double angle = 2 * M_PI * frame / 500.0;
    const double radius = std::hypot(start.position.x, start.position.z) + 0.5;
    camera.position = {radius * std::sin(angle), start.position.y + 0.5 * std::sin(3 * angle), radius * std::cos(angle)};
    camera.look = {-camera.position.x, -camera.position.y, -camera.position.z};
    return camera;
}

}  // namespace

TEST_CASE("soak: the API through 500 frames of a moving camera, resources flat", "[soak][api][kernel]") {
    bool haveCpu = false;
    for (const api::Device& device : api::listDevices()) haveCpu = haveCpu || device.cpu;
    if (!haveCpu) {
        ray::test::skip("no OpenCL CPU device");
        return;
    }
    // The bounds: a leak of 4 KiB a frame would pass 1.7 MiB; glibc's arenas and PoCL's
    // pools move a few hundred KiB between frames, so 4 MiB separates the two.
    constexpr long kMaxRssGrowthKiB = 4 * 1024;
    constexpr int kFrames = 500, kWarmUp = 50, kSampleEvery = 50;

    const api::Scene scene = api::Scene::load(ray::test::scenesDir() / "primitives_all.xml").scene;
    api::Settings settings;
    settings.width = 32;
    settings.height = 24;
    api::Renderer renderer(scene, "cpu");
    renderer.setSettings(settings);
    std::vector<std::pair<int, std::vector<float>>> samples;
    Resources start;
    for (int frame = 0; frame < kFrames; ++frame) {
        if (frame == kWarmUp) start = measure();
        renderer.setCamera(cameraAt(scene.camera(), frame));
        std::vector<float> rgb = renderer.render();
        if (frame % kSampleEvery == kSampleEvery - 1) samples.emplace_back(frame, std::move(rgb));
    }
    const Resources end = measure();
    std::cout << "soak api: " << kFrames << " frames; after " << kWarmUp << " (start) and at the end: resident "
              << start.rssKiB << " -> " << end.rssKiB << " KiB (bound: +" << kMaxRssGrowthKiB << "), descriptors "
              << start.descriptors << " -> " << end.descriptors << ", threads " << start.threads << " -> "
              << end.threads << " (bound: no growth)" << std::endl;
    CHECK(end.rssKiB - start.rssKiB < kMaxRssGrowthKiB);
    CHECK(end.descriptors <= start.descriptors);
    CHECK(end.threads <= start.threads);

    // Each sample against a fresh Renderer's render of its camera.
    for (const auto& [frame, rgb] : samples) {
        api::Scene fresh = scene;
        fresh.setCamera(cameraAt(scene.camera(), frame));
        api::Renderer renderer2(fresh, "cpu");
        renderer2.setSettings(settings);
        INFO("frame " << frame);
        CHECK(renderer2.render() == rgb);
    }
}
