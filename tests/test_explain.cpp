// ray explain: the tree of rays of one pixel, recorded from the reference renderer.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "explain/explanation_report.h"
#include "explain/pixel_explanation.h"
#include "reference/reference_renderer.h"
#include "scene/scene_loader.h"
#include "test_support.h"

using namespace ray;

namespace {

RenderSettings smallSettings(int width, int height, AntialiasMode aa) {
    RenderSettings s;
    s.width = width;
    s.height = height;
    s.antialias = aa;
    return s;
}

// Every ray of the explanation, depth first.
void forEachRay(const ExplainedRay& ray, const std::function<void(const ExplainedRay&)>& visit) {
    visit(ray);
    for (const auto& child : ray.children) forEachRay(*child, visit);
}

bool anyRay(const PixelExplanation& e, const std::function<bool(const ExplainedRay&)>& test) {
    bool found = false;
    for (const ExplainedSample& s : e.samples)
        if (s.ray) forEachRay(*s.ray, [&](const ExplainedRay& r) { found = found || test(r); });
    return found;
}

// The explanation's color is the stored pixel of the reference image, exactly, and its
// 8-bit value what a png would hold.
void requireMatchesImage(const PixelExplanation& e, const Image& image) {
    Vec3 stored = image.at(e.x, e.y);
    REQUIRE(e.color.x == stored.x);
    REQUIRE(e.color.y == stored.y);
    REQUIRE(e.color.z == stored.z);
    REQUIRE(e.bytes[0] == quantize8(stored.x));
    REQUIRE(e.bytes[1] == quantize8(stored.y));
    REQUIRE(e.bytes[2] == quantize8(stored.z));
}

// Explains every `step`-th pixel of the image and hands each explanation to `visit`.
void explainGrid(const Scene& scene, const RenderSettings& settings, int step,
                 const std::function<void(const PixelExplanation&)>& visit) {
    for (int y = step / 2; y < settings.height; y += step)
        for (int x = step / 2; x < settings.width; x += step) visit(explainPixel(scene, settings, x, y));
}

}  // namespace

TEST_CASE("explain on chess.xml: lit, shadowed (naming the occluder) and missed pixels match the reference image",
          "[explain]") {
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent");
        return;
    }
    Scene scene = loadScene(*shared / "cs123/scenes/chess.xml");
    RenderSettings settings = smallSettings(64, 48, AntialiasMode::Off);
    Image image = renderReference(scene, settings);

    int lit = 0, shadowed = 0, missed = 0;
    explainGrid(scene, settings, 4, [&](const PixelExplanation& e) {
        requireMatchesImage(e, image);
        REQUIRE(e.samples.size() == 1);
        const ExplainedRay& camera = *e.samples[0].ray;
        REQUIRE(camera.kind == TraceRayKind::Camera);
        if (!camera.hit) {
            ++missed;
            REQUIRE(e.color == Vec3{0, 0, 0});
            return;
        }
        REQUIRE(scene.primitives[size_t(camera.hitInfo.primitive)].sourceLine > 0);
        REQUIRE(camera.lights.size() == scene.lights.size());
        for (const TraceLightTerm& term : camera.lights) {
            if (term.shadowed) {
                ++shadowed;
                REQUIRE(std::string(term.unlitReason) == "shadowed");
                REQUIRE(term.occluder >= 0);
                REQUIRE(term.occluder != camera.hitInfo.primitive);
                std::string source = primitiveSource(scene, term.occluder);
                REQUIRE(source.rfind("chess.xml:", 0) == 0);
                REQUIRE(std::stoi(source.substr(10)) > 0);
                REQUIRE(term.contribution == Vec3{});
            } else if (!*term.unlitReason) {
                ++lit;
                REQUIRE(term.nDotL > 0);
                REQUIRE(term.attenuation > 0);
                REQUIRE(maxComponent(term.contribution) > 0);
            }
        }
        // Without reflective or transparent materials the color is the sum of the terms.
        Vec3 sum = camera.ambient + camera.emissive;
        for (const TraceLightTerm& term : camera.lights) sum += term.contribution;
        REQUIRE(std::abs(sum.x - camera.color.x) < 1e-12);
    });
    CHECK(lit > 0);
    CHECK(shadowed > 0);
    CHECK(missed > 0);
}

TEST_CASE("explain follows reflected and refracted branches with their weights", "[explain]") {
    Scene scene = loadScene(test::scenesDir() / "refraction.xml");
    RenderSettings settings = smallSettings(48, 36, AntialiasMode::Off);
    Image image = renderReference(scene, settings);

    int reflected = 0, refracted = 0, depthStops = 0;
    explainGrid(scene, settings, 3, [&](const PixelExplanation& e) {
        requireMatchesImage(e, image);
        anyRay(e, [&](const ExplainedRay& ray) {
            for (const auto& child : ray.children) {
                REQUIRE(child->depth == ray.depth + 1);
                // A branch's weight is its parent's times the factor applied to it.
                REQUIRE(std::abs(child->weight.x - ray.weight.x * child->factor.x) < 1e-12);
                if (child->kind == TraceRayKind::Reflected) ++reflected;
                if (child->kind == TraceRayKind::Refracted) ++refracted;
            }
            for (const ExplainedStop& stop : ray.stops) depthStops += stop.reason == BranchStop::DepthLimit;
            return false;
        });
    });
    CHECK(reflected > 0);
    CHECK(refracted > 0);

    SECTION("depth 0 stops every branch at the depth limit") {
        settings.maxDepth = 0;
        PixelExplanation e = explainPixel(scene, settings, 24, 18);
        const ExplainedRay& camera = *e.samples[0].ray;
        REQUIRE(camera.children.empty());
        if (camera.hit)
            for (const ExplainedStop& stop : camera.stops)
                CHECK((stop.reason == BranchStop::DepthLimit || stop.reason == BranchStop::NoCoefficient));
    }
}

TEST_CASE("explain with --fresnel: the image's colors, inner reflections weighted by R", "[explain][fresnel]") {
    Scene scene = loadScene(test::scenesDir() / "refraction.xml");
    RenderSettings settings = smallSettings(48, 36, AntialiasMode::Off);
    settings.fresnel = true;
    Image image = renderReference(scene, settings);

    int inner = 0, fresnelStops = 0;
    explainGrid(scene, settings, 3, [&](const PixelExplanation& e) {
        requireMatchesImage(e, image);
        anyRay(e, [&](const ExplainedRay& ray) {
            for (const auto& child : ray.children) {
                REQUIRE(std::abs(child->weight.x - ray.weight.x * child->factor.x) < 1e-12);
                // Met from inside, a ray splits into R reflected (kept inside) and 1 − R out.
                if (ray.hit && !ray.hitInfo.entering && child->kind == TraceRayKind::Reflected) {
                    ++inner;
                    REQUIRE(child->factor.x > 0);
                    REQUIRE(child->factor.x < 1);
                }
            }
            for (const ExplainedStop& stop : ray.stops) fresnelStops += stop.reason == BranchStop::NoFresnelShare;
            return false;
        });
    });
    CHECK(inner > 0);
    CHECK(fresnelStops > 0);  // total internal reflection: no transmitted branch
}

TEST_CASE("explain with course antialiasing reports every sample and the pixel the image holds", "[explain]") {
    Scene scene = loadScene(test::scenesDir() / "shadows.xml");
    RenderSettings settings = smallSettings(40, 30, AntialiasMode::Course);
    Image image = renderReference(scene, settings);
    explainGrid(scene, settings, 5, [&](const PixelExplanation& e) {
        requireMatchesImage(e, image);
        REQUIRE(e.samples.size() >= 4);
        for (const ExplainedSample& s : e.samples) REQUIRE(s.ray != nullptr);
    });
}

TEST_CASE("explain with the course's lens reports the 25 lens rays of each sample", "[explain][dof]") {
    Scene scene = loadScene(test::scenesDir() / "depth_of_field.xml");
    REQUIRE(scene.camera.aperture > 0);
    RenderSettings settings = smallSettings(24, 18, AntialiasMode::Off);
    Image image = renderReference(scene, settings);
    explainGrid(scene, settings, 6, [&](const PixelExplanation& e) {
        requireMatchesImage(e, image);
        REQUIRE(e.samples.size() == 1);
        const ExplainedSample& sample = e.samples[0];
        REQUIRE(sample.ray != nullptr);
        REQUIRE(sample.otherLensRays.size() == 24);
        // The sample is the mean of the lens rays' clamped colors (SPEC §3).
        Vec3 sum = clamp01(sample.ray->color);
        for (const auto& lensRay : sample.otherLensRays) {
            REQUIRE(lensRay->kind == TraceRayKind::Camera);
            sum = sum + clamp01(lensRay->color);
        }
        REQUIRE(sample.color.x == Approx(sum.x / 25).margin(1e-12));
        REQUIRE(sample.color.y == Approx(sum.y / 25).margin(1e-12));
        REQUIRE(sample.color.z == Approx(sum.z / 25).margin(1e-12));
        REQUIRE(explanationJson(e, scene)["samples"][0]["other_lens_rays"].size() == 24);
    });
    settings.dofMode = DofMode::Disk;
    PixelExplanation disk = explainPixel(scene, settings, 12, 9);
    REQUIRE(disk.samples[0].otherLensRays.empty());
}

TEST_CASE("explain's JSON names the hit primitive's file and line and every light term", "[explain]") {
    Scene scene = loadScene(test::scenesDir() / "shadows.xml");
    RenderSettings settings = smallSettings(40, 30, AntialiasMode::Off);
    bool sawHit = false;
    explainGrid(scene, settings, 5, [&](const PixelExplanation& e) {
        nlohmann::json j = explanationJson(e, scene);
        REQUIRE(j["bytes"][0] == e.bytes[0]);
        const nlohmann::json& ray = j["samples"][0]["ray"];
        if (!ray["hit"].get<bool>()) {
            REQUIRE(ray["stopped"] == "nothing hit");
            return;
        }
        sawHit = true;
        REQUIRE(ray["primitive"]["line"].get<int>() > 0);
        REQUIRE(ray["lights"].size() == scene.lights.size());
        for (const char* key : {"t", "normal", "uv", "ambient", "diffuse_color", "children", "branches_not_traced"})
            REQUIRE(ray.contains(key));
        // It parses back: nothing (such as an infinite distance) makes it invalid JSON.
        REQUIRE(nlohmann::json::parse(j.dump()) == j);
    });
    CHECK(sawHit);
}

TEST_CASE("explain refuses a pixel outside the image", "[explain]") {
    Scene scene = loadScene(test::scenesDir() / "shadows.xml");
    RenderSettings settings = smallSettings(8, 6, AntialiasMode::Off);
    REQUIRE_THROWS_AS(explainPixel(scene, settings, 8, 0), std::out_of_range);
    REQUIRE_THROWS_AS(explainPixel(scene, settings, 0, -1), std::out_of_range);
}

TEST_CASE("ray explain on chess.xml: the tree's 8-bit color is the pixel of ray --device ref --aa off", "[explain]") {
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent");
        return;
    }
    const std::string scene = (*shared / "cs123/scenes/chess.xml").string();
    const std::filesystem::path png = test::outputDir() / "explain_chess.png";
    const std::filesystem::path json = test::outputDir() / "explain_chess.json";
    REQUIRE(test::runRay({scene, "64", "48", "--device", "ref", "--aa", "off", "-o", png.string(), "--quiet"}).exitCode == 0);
    Image rendered = readImage(png);
    for (auto [x, y] : {std::pair{32, 30}, std::pair{10, 40}, std::pair{50, 20}, std::pair{2, 2}}) {
        auto result = test::runRay({"explain", scene, std::to_string(x), std::to_string(y), "64", "48", "--aa", "off",
                                    "--json", json.string()});
        REQUIRE(result.exitCode == 0);
        CHECK(result.output.find("pixel color") != std::string::npos);
        std::ifstream in(json);
        nlohmann::json j = nlohmann::json::parse(in);
        for (int c = 0; c < 3; ++c) {
            const double channel = c == 0 ? rendered.at(x, y).x : c == 1 ? rendered.at(x, y).y : rendered.at(x, y).z;
            REQUIRE(j["bytes"][c].get<int>() == int(std::lround(channel * 255)));
        }
    }
}

TEST_CASE("ray explain refuses bad arguments with exit status 2", "[explain]") {
    const std::string scene = (test::scenesDir() / "shadows.xml").string();
    CHECK(test::runRay({"explain", scene, "64", "0", "64", "48"}).exitCode == 2);  // x outside
    CHECK(test::runRay({"explain", scene, "1"}).exitCode == 2);                   // no y
    CHECK(test::runRay({"explain", scene, "1", "1", "--aa", "sideways"}).exitCode == 2);
    CHECK(test::runRay({"explain", (test::scenesDir() / "missing.xml").string(), "1", "1"}).exitCode == 2);
}

namespace {

// Every factor name in a JSON tree of rays.
void collectFactorNames(const nlohmann::json& ray, std::set<std::string>& names) {
    if (!ray.contains("children")) return;
    for (const auto& child : ray["children"]) {
        names.insert(child["factor_name"].get<std::string>());
        collectFactorNames(child, names);
    }
}

}  // namespace

TEST_CASE("explain names each branch's factor by its term of the lighting equation", "[explain]") {
    Scene scene = loadScene(test::scenesDir() / "refraction.xml");
    for (bool fresnel : {false, true}) {
        RenderSettings settings = smallSettings(32, 24, AntialiasMode::Off);
        settings.fresnel = fresnel;
        std::set<std::string> names;
        for (int y = 0; y < 24; y += 2)
            for (int x = 0; x < 32; x += 2) {
                const nlohmann::json tree = explanationJson(explainPixel(scene, settings, x, y), scene);
                for (const auto& sample : tree["samples"]) collectFactorNames(sample["ray"], names);
            }
        std::string all;
        for (const std::string& name : names) all += name + "; ";
        INFO("fresnel " << fresnel << ": " << all);
        if (!fresnel) {
            CHECK(names.count("ks·Or"));
            CHECK(names.count("kt·Ot"));
            CHECK(names.count("1 (kt·Ot was applied on entry)"));
        } else {
            CHECK(names.count("R·ks·Or"));
            CHECK(names.count("(1−R)·kt·Ot"));
        }
    }
    std::ostringstream text;
    RenderSettings settings = smallSettings(32, 24, AntialiasMode::Off);
    printExplanation(explainPixel(scene, settings, 16, 12), scene, text);
    CHECK_THAT(text.str(), Catch::Matchers::Contains("ka·Oa") && Catch::Matchers::Contains("D·(N·L)"));
}

TEST_CASE("explain shows a sample's shutter time only in a scene that moves", "[explain]") {
    RenderSettings settings = smallSettings(40, 30, AntialiasMode::Course);
    for (auto [name, moves] : {std::pair{"shadows.xml", false}, std::pair{"motion_blur.xml", true}}) {
        Scene scene = loadScene(test::scenesDir() / name);
        PixelExplanation explanation = explainPixel(scene, settings, 20, 15);
        std::ostringstream text;
        printExplanation(explanation, scene, text);
        INFO(name << ":\n" << text.str());
        CHECK((text.str().find("shutter time") != std::string::npos) == moves);
        CHECK(explanationJson(explanation, scene)["samples"][0].contains("time") == moves);
    }
}
