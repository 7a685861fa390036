// The stochastic sampling modes (issue 4): adaptive antialiasing in both renderers, and
// the noise of stochastic features falling as 1/√samples.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "reference/course_sampling.h"
#include "kernel_comparison.h"

namespace fs = std::filesystem;
using namespace ray;

namespace {

double rmsDifference(const Image& a, const Image& b) {
    double sum = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        double d = double(a.rgb[i]) - double(b.rgb[i]);
        sum += d * d;
    }
    return std::sqrt(sum / double(a.rgb.size()));
}

Scene loadQuietly(const fs::path& file) {
    LoadOptions load;
    load.warn = [](const std::string&) {};
    return loadScene(file, load);
}

}  // namespace

TEST_CASE("adaptive sampling refines only where the first samples disagree", "[stochastic]") {
    int taken = 0;
    auto flat = [](double, double) { return Vec3{0.5, 0.5, 0.5}; };
    CHECK(sampleAdaptive(flat, 16, 3, 0, &taken).x == Approx(0.5));
    CHECK(taken == 4);
    auto edge = [](double sx, double) { return sx < 0.5 ? Vec3{0, 0, 0} : Vec3{1, 1, 1}; };
    Vec3 c = sampleAdaptive(edge, 16, 3, 0, &taken);
    CHECK(taken == 4 + 16);
    CHECK(c.x == Approx(0.5).margin(0.01));  // 2 of 4 and 8 of 16 lie right of the edge
    // Deterministic for a seed, different across seeds.
    auto noisy = [](double sx, double sy) { return Vec3{sx, sy, 0}; };
    CHECK(sampleAdaptive(noisy, 16, 7, 1).x == sampleAdaptive(noisy, 16, 7, 1).x);
    CHECK(sampleAdaptive(noisy, 16, 7, 1).x != sampleAdaptive(noisy, 16, 7, 2).x);
}

TEST_CASE("kernel matches host with adaptive sampling", "[kernel][kvh][stochastic]") {
    auto device = test::cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    RenderSettings settings = test::settingsFromOptions("--aa adaptive --samples 16 --seed 5", 96, 72);
    for (const char* scene : {"light_area.xml", "showpiece.xml"}) {
        SECTION(scene) {
            test::compareKernelWithHost(*device, test::scenesDir() / scene, settings,
                                  std::string("adaptive_") + fs::path(scene).stem().string());
        }
    }
}

// Stratified sampling of a scene lit by an area light with one light sample per camera
// sample: the error against a 1024-sample render must fall about as 1/√samples (a slope
// of −1/2 on a log–log plot; edges, which stratification resolves faster, steepen it a
// little).
TEST_CASE("stochastic noise falls as 1/sqrt(samples)", "[stochastic]") {
    Scene scene = loadQuietly(test::scenesDir() / "light_area.xml");
    auto render = [&](int samples, uint32_t seed) {
        RenderSettings s = test::settingsFromOptions("--aa stratified --samples " + std::to_string(samples) +
                                                         " --seed " + std::to_string(seed),
                                                     32, 24);
        s.areaSamples = 1;
        return renderReference(scene, s);
    };
    Image truth = render(1024, 99);
    std::vector<int> counts = {4, 16, 64};
    std::vector<double> errors;
    for (int n : counts) {
        errors.push_back(rmsDifference(render(n, 1), truth));
        std::printf("samples %4d: rms error %.5f, × sqrt(samples) %.4f\n", n, errors.back(),
                    errors.back() * std::sqrt(double(n)));
    }
    for (size_t i = 1; i < counts.size(); ++i) {
        double slope = std::log(errors[i] / errors[i - 1]) / std::log(double(counts[i]) / double(counts[i - 1]));
        INFO("log-log slope from " << counts[i - 1] << " to " << counts[i] << " samples: " << slope);
        CHECK(slope < -0.35);
        CHECK(slope > -0.85);
    }
}
