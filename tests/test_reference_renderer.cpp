// The reference renderer on scenes built in code, checked against the formulas of SPEC §3-§4
// worked out by hand; and the sampling patterns it uses.
//
// Most lighting tests render a single pixel: the camera sits at (0, 0, 5) looking down −z, so
// the one camera ray of a 1×1 image with --aa off goes straight down the axis and meets the
// front face (z = 0) of a wide slab at the origin, where N = V = (0, 0, 1).
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <set>
#include <utility>
#include <vector>

#include "reference/course_sampling.h"
#include "core/random.h"
#include "reference/reference_bvh.h"
#include "reference/reference_renderer.h"

using namespace ray;

namespace {

void requireColor(const Vec3& actual, const Vec3& expected, double eps = 1e-6) {
    INFO("actual (" << actual.x << ", " << actual.y << ", " << actual.z << "), expected (" << expected.x << ", "
                    << expected.y << ", " << expected.z << ")");
    REQUIRE(actual.x == Approx(expected.x).margin(eps));
    REQUIRE(actual.y == Approx(expected.y).margin(eps));
    REQUIRE(actual.z == Approx(expected.z).margin(eps));
}

int addMaterial(Scene& scene, const Material& material) {
    scene.materials.push_back(material);
    return int(scene.materials.size()) - 1;
}

void addInstance(Scene& scene, PrimitiveType type, const Affine& objectToWorld, int material) {
    PrimitiveInstance instance;
    instance.type = type;
    instance.objectToWorld = objectToWorld;
    instance.worldToObject = objectToWorld.inverse();
    instance.material = material;
    scene.primitives.push_back(instance);
}

// A 20×20×1 slab whose front face is the plane z = z0, facing +z (or −z when facing back).
void addSlab(Scene& scene, double z0, int material, bool facingBack = false) {
    double centre = facingBack ? z0 + 0.5 : z0 - 0.5;
    addInstance(scene, PrimitiveType::Cube, Affine::translation({0, 0, centre}) * Affine::scaling({20, 20, 1}),
                material);
}

void addSphere(Scene& scene, const Vec3& centre, double radius, int material) {
    addInstance(scene, PrimitiveType::Sphere,
                Affine::translation(centre) * Affine::scaling({2 * radius, 2 * radius, 2 * radius}), material);
}

// The camera of the one-pixel tests, and distinct global coefficients so that a swapped
// one shows.
Scene onePixelScene() {
    Scene scene;
    scene.camera.position = {0, 0, 5};
    scene.camera.look = {0, 0, -1};
    scene.camera.up = {0, 1, 0};
    scene.globals = {0.5, 0.7, 0.3, 0.5};
    return scene;
}

RenderSettings onePixelSettings() {
    RenderSettings settings;
    settings.width = settings.height = 1;
    settings.antialias = AntialiasMode::Off;
    return settings;
}

Vec3 renderOnePixel(const Scene& scene, const RenderSettings& settings = onePixelSettings(),
                    RayCounts* counts = nullptr) {
    Image image = renderReference(scene, settings, {}, counts);
    REQUIRE(image.width == 1);
    return image.at(0, 0);
}

Light pointLight(const Vec3& position, const Vec3& color = {1, 1, 1}, const Vec3& attenuation = {1, 0, 0}) {
    Light light;
    light.type = LightType::Point;
    light.position = position;
    light.color = color;
    light.attenuation = attenuation;
    return light;
}

Light directionalLight(const Vec3& direction, const Vec3& color = {1, 1, 1}) {
    Light light;
    light.type = LightType::Directional;
    light.direction = direction;
    light.color = color;
    return light;
}

Material diffuseMaterial(const Vec3& diffuse) {
    Material m;
    m.diffuse = diffuse;
    return m;
}

}  // namespace

TEST_CASE("ambient and emissive terms: ka·Oa + Oe", "[lighting]") {
    Scene scene = onePixelScene();
    Material m;
    m.ambient = {0.2, 0.4, 0.6};
    m.emissive = {0.1, 0, 0};
    addSlab(scene, 0, addMaterial(scene, m));
    requireColor(renderOnePixel(scene), {0.2, 0.2, 0.3});
}

TEST_CASE("a ray that leaves the scene is black", "[lighting]") {
    Scene scene = onePixelScene();
    scene.lights.push_back(pointLight({0, 0, 2}));
    requireColor(renderOnePixel(scene), {0, 0, 0});
}

TEST_CASE("point light: diffuse, specular and attenuation", "[lighting]") {
    Scene scene = onePixelScene();
    Material m = diffuseMaterial({0.5, 0.5, 0.5});
    m.specular = {1, 1, 1};
    m.shininess = 10;
    addSlab(scene, 0, addMaterial(scene, m));

    SECTION("straight above: N·L = R·V = 1, f_att = 1/(c1 + c2·d + c3·d²)") {
        scene.lights.push_back(pointLight({0, 0, 2}, {1, 0.5, 0.25}, {1, 0.5, 0.25}));
        const double attenuation = 1.0 / (1 + 0.5 * 2 + 0.25 * 4);
        const double response = 0.7 * 0.5 + 0.3 * 1;
        requireColor(renderOnePixel(scene), Vec3{1, 0.5, 0.25} * (attenuation * response));
    }
    SECTION("oblique: N·L = R·V = 0.8, highlight 0.8^n") {
        scene.lights.push_back(pointLight({3, 0, 4}));
        const double response = 0.7 * 0.5 * 0.8 + 0.3 * std::pow(0.8, 10);
        requireColor(renderOnePixel(scene), Vec3{1, 1, 1} * response);
    }
    SECTION("attenuation never brightens: min(1, 1/(c1 + …))") {
        scene.lights.push_back(pointLight({0, 0, 2}, {1, 1, 1}, {0.5, 0, 0}));
        requireColor(renderOnePixel(scene), Vec3{1, 1, 1} * (0.7 * 0.5 + 0.3));
    }
}

TEST_CASE("a light adds nothing where N·L ≤ 0, not even a highlight", "[lighting]") {
    Scene scene = onePixelScene();
    Material m = diffuseMaterial({1, 1, 1});
    m.specular = {1, 1, 1};
    m.shininess = 0;  // max(R·V, 0)^0 would be 1 everywhere
    addSlab(scene, 0, addMaterial(scene, m));
    scene.lights.push_back(pointLight({5, 0, 0}));   // in the surface's plane: N·L = 0
    scene.lights.push_back(pointLight({0, 0, -3}));  // behind it
    RenderSettings settings = onePixelSettings();
    settings.shadows = false;
    RayCounts counts;
    requireColor(renderOnePixel(scene, settings, &counts), {0, 0, 0});
    REQUIRE(counts.shadow == 0);
}

TEST_CASE("directional light: L = −direction, no attenuation", "[lighting]") {
    Scene scene = onePixelScene();
    addSlab(scene, 0, addMaterial(scene, diffuseMaterial({1, 0.5, 0})));
    Light light = directionalLight({0, -0.6, -0.8}, {0.5, 1, 1});
    light.attenuation = {0, 0, 100};  // ignored for directional lights
    scene.lights.push_back(light);
    requireColor(renderOnePixel(scene), Vec3{0.5, 0.5, 0} * (0.7 * 0.8));
}

TEST_CASE("spot light: full inside angle − penumbra, smooth falloff, nothing outside", "[lighting]") {
    // θ is the angle between the spot's axis and the way to the point: the spot sits straight
    // above the point and its axis is tilted by θ.
    auto litBySpot = [](double thetaDegrees) {
        Scene scene = onePixelScene();
        addSlab(scene, 0, addMaterial(scene, diffuseMaterial({1, 1, 1})));
        Light spot = pointLight({0, 0, 4});
        spot.type = LightType::Spot;
        double theta = radians(thetaDegrees);
        spot.direction = {std::sin(theta), 0, -std::cos(theta)};
        spot.angleDegrees = 30;
        spot.penumbraDegrees = 20;  // inner 10°
        scene.lights.push_back(spot);
        return renderOnePixel(scene).x / 0.7;  // kd·Od·N·L = 0.7
    };
    auto smoothFalloff = [](double x) { return 1 - (3 * x * x - 2 * x * x * x); };
    REQUIRE(litBySpot(0) == Approx(1));
    REQUIRE(litBySpot(5) == Approx(1));
    REQUIRE(litBySpot(12.5) == Approx(smoothFalloff(0.125)));
    REQUIRE(litBySpot(20) == Approx(0.5));
    REQUIRE(litBySpot(27) == Approx(smoothFalloff(0.85)));
    REQUIRE(litBySpot(30) == Approx(0).margin(1e-12));
    REQUIRE(litBySpot(35) == Approx(0).margin(1e-12));
}

TEST_CASE("shadows: anything between the point and the light", "[lighting]") {
    Scene scene = onePixelScene();
    Material m = diffuseMaterial({1, 1, 1});
    m.ambient = {0.2, 0.2, 0.2};
    addSlab(scene, 0, addMaterial(scene, m));
    const int blockerMaterial = addMaterial(scene, diffuseMaterial({1, 1, 1}));
    const Vec3 ambient{0.1, 0.1, 0.1};
    const Vec3 lit = ambient + Vec3{1, 1, 1} * (0.7 * std::sqrt(0.5));  // N·L = cos 45°

    SECTION("point light with a blocker halfway: only ambient, and one shadow ray") {
        scene.lights.push_back(pointLight({2, 0, 2}));
        addSphere(scene, {1, 0, 1}, 0.25, blockerMaterial);
        RayCounts counts;
        requireColor(renderOnePixel(scene, onePixelSettings(), &counts), ambient);
        REQUIRE(counts.primary == 1);
        REQUIRE(counts.shadow == 1);
        REQUIRE(counts.secondary == 0);

        RenderSettings noShadows = onePixelSettings();
        noShadows.shadows = false;
        requireColor(renderOnePixel(scene, noShadows, &counts), lit);
        REQUIRE(counts.shadow == 0);
    }
    SECTION("point light with the blocker beyond the light: lit") {
        scene.lights.push_back(pointLight({2, 0, 2}));
        addSphere(scene, {3, 0, 3}, 0.25, blockerMaterial);
        requireColor(renderOnePixel(scene), lit);
    }
    SECTION("directional light: a blocker anywhere along L") {
        scene.lights.push_back(directionalLight({-1, 0, -1}));
        addSphere(scene, {10, 0, 10}, 0.25, blockerMaterial);
        requireColor(renderOnePixel(scene), ambient);
    }
    SECTION("a shadow ray does not hit the surface it leaves, even at a grazing angle") {
        scene.lights.push_back(pointLight({1000, 0, 1}));
        requireColor(renderOnePixel(scene), ambient + Vec3{1, 1, 1} * (0.7 * 1 / std::hypot(1000.0, 1.0)), 1e-9);
    }
}

TEST_CASE("normals go to world space by the inverse transpose (non-uniform scale)", "[lighting]") {
    // A sphere stretched to semi-axes (1, 0.5, 0.5), seen straight down −z at x = 0.6, where
    // its surface is at z = 0.4 and the true normal ∝ (x/1², 0, z/0.5²) = (0.6, 0, 1.6).
    Scene scene = onePixelScene();
    scene.camera.position = {0.6, 0, 5};
    addInstance(scene, PrimitiveType::Sphere, Affine::scaling({2, 1, 1}), addMaterial(scene, diffuseMaterial({1, 1, 1})));
    scene.lights.push_back(directionalLight({0, 0, -1}));  // L = +z: N·L is the normal's z
    const double normalZ = 1.6 / std::hypot(0.6, 1.6);
    requireColor(renderOnePixel(scene), Vec3{1, 1, 1} * (0.7 * normalZ));
}

TEST_CASE("rays from inside a primitive see its inner side, normal facing them", "[lighting]") {
    Scene scene = onePixelScene();
    scene.camera.position = {0, 0, 0};
    addSphere(scene, {0, 0, 0}, 2, addMaterial(scene, diffuseMaterial({1, 1, 1})));
    scene.lights.push_back(pointLight({0, 0, 0}));
    RenderSettings settings = onePixelSettings();
    requireColor(renderOnePixel(scene, settings), Vec3{1, 1, 1} * 0.7);
}

TEST_CASE("textures: D = blend·T + (1 − blend)·kd·Od", "[lighting][uv]") {
    Scene scene = onePixelScene();
    Image texture(2, 2);
    texture.set(0, 0, {1, 0, 0});
    texture.set(1, 0, {0, 1, 0});
    texture.set(0, 1, {0, 0, 1});
    texture.set(1, 1, {1, 1, 0});  // the texel at s = t = 0.5: column 1, row 1
    scene.images.push_back(texture);
    Material m = diffuseMaterial({1, 1, 1});
    m.texture.image = 0;
    m.blend = 0.25;
    addSlab(scene, 0, addMaterial(scene, m));  // the camera ray meets the face's centre: u = v = 0.5
    scene.lights.push_back(directionalLight({0, 0, -1}));

    requireColor(renderOnePixel(scene), Vec3{1, 1, 0} * 0.25 + Vec3{1, 1, 1} * (0.75 * 0.7));
    RenderSettings noTextures = onePixelSettings();
    noTextures.textures = false;
    requireColor(renderOnePixel(scene, noTextures), Vec3{1, 1, 1} * 0.7);
    SECTION("a texture whose file was missing (an empty image) is no texture") {
        scene.images[0] = Image();
        requireColor(renderOnePixel(scene), Vec3{1, 1, 1} * 0.7);
    }
}

// Refraction through a slab with nothing behind it: the refracted ray leaves the scene and
// adds black (SPEC §4), so only the slab's own shading remains.
TEST_CASE("a transparent surface with nothing behind it keeps only its own shading", "[lighting]") {
    Scene scene = onePixelScene();
    Material m = diffuseMaterial({1, 1, 1});
    m.transparent = {1, 1, 1};
    m.ior = 1.5;
    addSlab(scene, 0, addMaterial(scene, m));
    scene.lights.push_back(directionalLight({0, 0, -1}));
    requireColor(renderOnePixel(scene), Vec3{1, 1, 1} * 0.7);
}

// SPEC §4: met from inside, a transparent surface adds nothing of its own and passes on
// clamp(I_t) with weight 1, so kt·Ot applies once per object: through a glowing glass slab
// (emission E) to a glowing wall (W), the camera sees E + kt·Ot·W, not E + kt·Ot·(E + kt·Ot·W).
TEST_CASE("a transparent surface met from inside passes on what lies beyond, once weighted", "[lighting]") {
    Scene scene = onePixelScene();
    Material glass = diffuseMaterial({0, 0, 0});
    glass.emissive = {0.1, 0.2, 0.3};
    glass.transparent = {1, 1, 1};
    glass.ior = 1.5;
    addSlab(scene, 0, addMaterial(scene, glass));
    Material wall = diffuseMaterial({0, 0, 0});
    wall.emissive = {0.4, 0.2, 0.6};
    addSlab(scene, -5, addMaterial(scene, wall));
    const double kt = scene.globals.kt;
    requireColor(renderOnePixel(scene), glass.emissive + kt * wall.emissive);
}

namespace {

// Two parallel mirrors: the slab at z = 0 (emitting E0) and one facing it at z = 10
// (emitting E1); the camera between them sees the first, the reflection bounces between.
struct MirrorPair {
    Scene scene = onePixelScene();
    Vec3 emitted[2] = {{0.1, 0.2, 0.3}, {0.4, 0.3, 0.2}};
    double k = 0;  // ks·Or, the weight of each bounce

    explicit MirrorPair(double reflective) {
        for (int side = 0; side < 2; ++side) {
            Material m = diffuseMaterial({0, 0, 0});
            m.emissive = emitted[side];
            m.reflective = {reflective, reflective, reflective};
            addSlab(scene, side == 0 ? 0 : 10, addMaterial(scene, m), side == 1);
        }
        k = scene.globals.ks * reflective;
    }

    // SPEC §4 by hand: each hit adds its emission and k·clamp(what its reflection sees).
    Vec3 expected(int bounce, int maxDepth, double weight, double threshold) const {
        Vec3 color = emitted[bounce % 2];
        if (bounce < maxDepth && weight * k >= threshold)
            color += k * clamp01(expected(bounce + 1, maxDepth, weight * k, threshold));
        return color;
    }
};

}  // namespace

TEST_CASE("reflection: ks·Or·I_r, depth limit, weight threshold", "[lighting]") {
    MirrorPair mirrors(1.0);
    RenderSettings settings = onePixelSettings();
    settings.weightThreshold = 0;

    SECTION("depth d: at most d bounces after the camera ray") {
        for (int depth = 0; depth <= 5; ++depth) {
            INFO("depth " << depth);
            settings.maxDepth = depth;
            RayCounts counts;
            requireColor(renderOnePixel(mirrors.scene, settings, &counts), mirrors.expected(0, depth, 1, 0));
            REQUIRE(counts.secondary == uint64_t(depth));
        }
    }
    SECTION("a branch stops when its weight falls below the threshold in every channel") {
        settings.maxDepth = 10;
        settings.weightThreshold = 0.05;  // k = ks·Or = 0.3: weights 0.3, 0.09 pass; 0.027 does not
        RayCounts counts;
        requireColor(renderOnePixel(mirrors.scene, settings, &counts), mirrors.expected(0, 10, 1, 0.05));
        REQUIRE(counts.secondary == 2);
    }
    SECTION("one channel above the threshold keeps the branch going") {
        mirrors.scene.materials[0].reflective = {1, 0.01, 0.01};
        mirrors.scene.materials[1].reflective = {1, 0.01, 0.01};
        settings.maxDepth = 3;
        settings.weightThreshold = 0.02;  // red: 0.3, 0.09, 0.027 pass; green and blue fail at once
        RayCounts counts;
        renderOnePixel(mirrors.scene, settings, &counts);
        REQUIRE(counts.secondary == 3);
    }
    SECTION("I_r is clamped to [0, 1] before it is weighted") {
        mirrors.scene.materials[1].emissive = {3, 3, 3};
        settings.maxDepth = 1;
        requireColor(renderOnePixel(mirrors.scene, settings), mirrors.emitted[0] + Vec3{1, 1, 1} * mirrors.k);
    }
    SECTION("switched off") {
        settings.maxDepth = 4;
        settings.reflections = false;
        RayCounts counts;
        requireColor(renderOnePixel(mirrors.scene, settings, &counts), mirrors.emitted[0]);
        REQUIRE(counts.secondary == 0);
    }
}

namespace {

// Facing an emissive-looking wall at z = −1 whose texture records where it was hit: the
// +z face of a cube scaled to 8×8, so that the color of wall point (x, y) is
// ((x + 4)/8, (y + 4)/8) to within half a texel (1/800).
Scene wallScene() {
    Scene scene;
    scene.camera.position = {0, 0, 0};
    scene.camera.look = {0, 0, -2};
    scene.camera.up = {0, 3, 0};
    scene.camera.heightAngleDegrees = 90;
    scene.globals.kd = 1;
    Image ramp(400, 400);
    for (int y = 0; y < 400; ++y)
        for (int x = 0; x < 400; ++x) ramp.set(x, y, {(x + 0.5) / 400, 1 - (y + 0.5) / 400, 0});
    scene.images.push_back(ramp);
    Material wall = diffuseMaterial({0, 0, 0});
    wall.texture.image = 0;
    wall.blend = 1;
    addInstance(scene, PrimitiveType::Cube, Affine::translation({0, 0, -1.5}) * Affine::scaling({8, 8, 1}),
                addMaterial(scene, wall));
    scene.lights.push_back(directionalLight({0, 0, -1}));  // N·L = 1: the color is the texel
    return scene;
}

// The wall point whose color this is.
std::pair<double, double> wallPoint(const Vec3& color) { return {color.x * 8 - 4, color.y * 8 - 4}; }

}  // namespace

TEST_CASE("camera rays: the image plane of SPEC §3", "[reference]") {
    // A 4×2 image at heightangle 90° (h = 1, w = 2): pixel (i, j)'s centre looks through
    // (u·w, v·h, −1) with u = 2(i + 0.5)/4 − 1, v = 1 − 2(j + 0.5)/2.
    RenderSettings settings;
    settings.width = 4;
    settings.height = 2;
    settings.antialias = AntialiasMode::Off;
    Image image = renderReference(wallScene(), settings);
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 4; ++i) {
            double u = 2 * (i + 0.5) / 4 - 1, v = 1 - 2 * (j + 0.5) / 2;
            auto [x, y] = wallPoint(image.at(i, j));
            INFO("pixel " << i << ", " << j);
            REQUIRE(x == Approx(u * 2).margin(0.011));
            REQUIRE(y == Approx(v * 1).margin(0.011));
        }
    }
}

TEST_CASE("depth of field, disk lens (--dof disk): a random point of a lens of diameter aperture, focused at focallength",
          "[reference][dof]") {
    Scene scene = wallScene();
    scene.camera.aperture = 0.5;
    RenderSettings settings = onePixelSettings();
    settings.seed = 3;
    settings.dofMode = DofMode::Disk;

    SECTION("switched off, or focused on the wall: the pinhole's point") {
        scene.camera.focalLength = 1;
        for (bool on : {false, true}) {
            settings.depthOfField = on;
            auto [x, y] = wallPoint(renderOnePixel(scene, settings));
            REQUIRE(x == Approx(0).margin(0.011));
            REQUIRE(y == Approx(0).margin(0.011));
        }
    }
    SECTION("focused halfway: the ray from lens point (lx, ly) through (0, 0, −0.5) meets the wall at (−lx, −ly)") {
        scene.camera.focalLength = 0.5;
        // Sample 0 of pixel 0; the lens point from dimensions 2 and 3, uniform on the disk.
        double r = 0.25 * std::sqrt(sampleRandom(0, 0, 2, 3)), phi = 2 * kPi * sampleRandom(0, 0, 3, 3);
        auto [x, y] = wallPoint(renderOnePixel(scene, settings));
        REQUIRE(x == Approx(-r * std::cos(phi)).margin(0.011));
        REQUIRE(y == Approx(-r * std::sin(phi)).margin(0.011));
        REQUIRE(std::hypot(x, y) > 0.03);  // this seed's lens point is well off centre
    }
}

namespace {

// wallScene's wall with a 50×50 checker of black and white texels (0.16 wide) instead of
// the ramp, lit head on by `light`: a ray's color is exactly 0 or light.
Scene checkerWallScene(double light) {
    Scene scene = wallScene();
    Image checker(50, 50);
    for (int y = 0; y < 50; ++y)
        for (int x = 0; x < 50; ++x) checker.set(x, y, Vec3{1, 1, 1} * double((x + y) % 2));
    scene.images[0] = checker;
    scene.lights[0].color = {light, light, light};
    scene.camera.aperture = 0.5;  // lens points up to ±0.5 along U and V
    return scene;
}

// A 16×8 image (w = 2, h = 1): its pixel centres see wall points well inside texels.
RenderSettings wideSettings(DofMode mode) {
    RenderSettings settings = onePixelSettings();
    settings.width = 16;
    settings.height = 8;
    settings.dofMode = mode;
    return settings;
}

}  // namespace

// SPEC §3: the course's lens is a 5×5 grid of points pos + (i·a/2)·U + (j·a/2)·V whose rays
// all aim where the pinhole ray meets the plane at depth focallength along the look axis.
TEST_CASE("course depth of field: focused on the plane at depth focallength, not at that distance", "[reference][dof]") {
    // The wall is the plane at depth 1: focused there, every lens ray of a pixel meets the
    // pinhole ray's wall point, even in the corners, where the point at distance 1 along
    // the ray lies at depth 0.43 and a lens focused there would blur the checker.
    Scene scene = checkerWallScene(1);
    scene.camera.focalLength = 1;
    Image lens = renderReference(scene, wideSettings(DofMode::Course));
    scene.camera.aperture = 0;
    Image pinhole = renderReference(scene, wideSettings(DofMode::Course));
    REQUIRE(lens.rgb.size() == pinhole.rgb.size());
    for (size_t k = 0; k < lens.rgb.size(); ++k) REQUIRE(lens.rgb[k] == Approx(pinhole.rgb[k]).margin(1e-6));
    scene.camera.aperture = 0.5;
    Image disk = renderReference(scene, wideSettings(DofMode::Disk));  // focused at distance 1: blurred
    size_t differing = 0;
    for (size_t k = 0; k < disk.rgb.size(); ++k) differing += std::abs(disk.rgb[k] - pinhole.rgb[k]) > 0.5f;
    REQUIRE(differing > 0);
}

TEST_CASE("course depth of field: the mean of 25 lens rays, each clamped", "[reference][dof]") {
    // Out of focus (the plane at depth 0.5), a pixel's lens rays meet different checker
    // texels, each 0 or 3 (a light of intensity 3) before clamping and 0 or 1 after: the
    // pixel is k/25 for k lens rays on white, never above 1.
    Scene scene = checkerWallScene(3);
    scene.camera.focalLength = 0.5;
    RayCounts counts;
    RenderSettings settings = wideSettings(DofMode::Course);
    Image image = renderReference(scene, settings, {}, &counts);
    CHECK(counts.primary == uint64_t(25 * settings.width * settings.height));
    int blurred = 0;
    for (float value : image.rgb) {
        const double k = double(value) * 25;
        REQUIRE(k == Approx(std::round(k)).margin(1e-4));
        REQUIRE(value >= 0);
        REQUIRE(value <= 1);
        blurred += std::round(k) > 0 && std::round(k) < 25;
    }
    CHECK(blurred > int(image.rgb.size()) / 2);
    // --dof disk: one lens ray a sample, unclamped under --aa off: 0 or 3.
    Image disk = renderReference(scene, wideSettings(DofMode::Disk), {}, &counts);
    CHECK(counts.primary == uint64_t(settings.width * settings.height));
    for (float value : disk.rgb) REQUIRE((value == Approx(0).margin(1e-6) || value == Approx(3).margin(1e-6)));
}

namespace {

// A deterministic jumble of every supported primitive, mirrors and lights, for comparing
// whole renders.
Scene randomScene(int count) {
    Scene scene;
    scene.camera.position = {0, 2, 12};
    scene.camera.look = {0, -0.15, -1};
    uint32_t counter = 0;
    auto random = [&counter](double lo, double hi) { return lo + (hi - lo) * sampleRandom(counter++, 0, 0, 0); };
    for (int i = 0; i < 6; ++i) {
        Material m = diffuseMaterial({random(0, 1), random(0, 1), random(0, 1)});
        m.ambient = {0.1, 0.1, 0.1};
        m.specular = {1, 1, 1};
        m.shininess = 20;
        if (i % 2) m.reflective = {0.8, 0.8, 0.8};
        addMaterial(scene, m);
    }
    const PrimitiveType types[4] = {PrimitiveType::Cube, PrimitiveType::Sphere, PrimitiveType::Cylinder,
                                    PrimitiveType::Cone};
    for (int i = 0; i < count; ++i) {
        Affine transform = Affine::translation({random(-5, 5), random(-4, 4), random(-5, 5)}) *
                           Affine::rotation({random(-1, 1), random(-1, 1), random(0.1, 1)}, random(0, 360)) *
                           Affine::scaling({random(0.2, 1.5), random(0.2, 1.5), random(0.2, 1.5)});
        addInstance(scene, types[i % 4], transform, i % 6);
    }
    scene.lights.push_back(pointLight({4, 8, 6}, {0.7, 0.7, 0.7}, {1, 0.02, 0}));
    scene.lights.push_back(directionalLight({-1, -2, -0.5}, {0.4, 0.4, 0.5}));
    Light spot = pointLight({-3, 6, 4}, {0.6, 0.5, 0.3});
    spot.type = LightType::Spot;
    spot.direction = {0.3, -1, -0.4};
    spot.angleDegrees = 35;
    spot.penumbraDegrees = 15;
    scene.lights.push_back(spot);
    return scene;
}

RenderSettings smallCourseSettings() {
    RenderSettings settings;
    settings.width = 48;
    settings.height = 36;
    settings.antialias = AntialiasMode::Course;
    return settings;
}

}  // namespace

TEST_CASE("the BVH finds exactly what brute force finds", "[reference]") {
    const Scene scene = randomScene(240);
    const RenderSettings settings = smallCourseSettings();
    ReferenceRenderOptions bvh, bruteForce;
    bruteForce.bruteForce = true;
    RayCounts bvhCounts, bruteForceCounts;
    Image withBvh = renderReference(scene, settings, bvh, &bvhCounts);
    Image withoutBvh = renderReference(scene, settings, bruteForce, &bruteForceCounts);
    REQUIRE(withBvh.rgb == withoutBvh.rgb);
    REQUIRE(bvhCounts.total() == bruteForceCounts.total());
    REQUIRE(bvhCounts.secondary > 0);
    REQUIRE(bvhCounts.shadow > 0);
}

// Squares flush with the top of a slab, as a chessboard's are with its border: every hit
// on the top is a tie between two primitives at exactly the same distance, which the BVH
// must settle as brute force does (the one listed last wins, SPEC §4), not by its visiting
// order.
TEST_CASE("the BVH settles ties between coplanar faces as brute force does", "[reference]") {
    Scene scene;
    scene.camera.position = {0, 6, 7};
    scene.camera.look = {0, -6, -7};
    addMaterial(scene, diffuseMaterial({0.2, 0.2, 0.8}));  // the slab
    addMaterial(scene, diffuseMaterial({0.9, 0.9, 0.9}));  // light squares
    addMaterial(scene, diffuseMaterial({0.1, 0.1, 0.1}));  // dark squares
    // The squares first, then the slab, then squares again: whichever the BVH visits
    // first, some ties must go to the square and others to the slab.
    auto addSquares = [&](int firstRow, int lastRow) {
        for (int row = firstRow; row < lastRow; ++row)
            for (int column = 0; column < 8; ++column)
                addInstance(scene, PrimitiveType::Cube,
                            Affine::translation({column - 3.5, 0, row - 3.5}) * Affine::scaling({1, 0.5, 1}),
                            1 + (row + column) % 2);
    };
    addSquares(0, 4);
    addInstance(scene, PrimitiveType::Cube, Affine::scaling({8, 0.5, 8}), 0);
    addSquares(4, 8);
    scene.lights.push_back(pointLight({2, 8, 5}, {1, 1, 1}));
    RenderSettings settings = smallCourseSettings();
    settings.antialias = AntialiasMode::Off;
    ReferenceRenderOptions bvh, bruteForce;
    bruteForce.bruteForce = true;
    Image withBvh = renderReference(scene, settings, bvh);
    Image withoutBvh = renderReference(scene, settings, bruteForce);
    int differing = 0;
    for (size_t p = 0; p < withBvh.rgb.size(); p += 3)
        if (!std::equal(&withBvh.rgb[p], &withBvh.rgb[p] + 3, &withoutBvh.rgb[p])) ++differing;
    REQUIRE(differing == 0);
    // Both kinds of tie occur: the top shows the slab where rows 0-3 lie (listed before
    // it) and the squares of rows 4-7 (listed after), so both square colours and the
    // slab's blue appear.
    bool slabSeen = false, squareSeen = false;
    for (size_t p = 0; p < withBvh.rgb.size(); p += 3) {
        if (withBvh.rgb[p + 2] > withBvh.rgb[p] + 0.1f) slabSeen = true;
        if (withBvh.rgb[p] > 0.3f && std::abs(withBvh.rgb[p] - withBvh.rgb[p + 2]) < 1e-6f) squareSeen = true;
    }
    REQUIRE(slabSeen);
    REQUIRE(squareSeen);
}

// SPEC §4: at exactly the same distance the primitive listed last wins, in the BVH's search
// and brute force's alike, whichever it visits first.
TEST_CASE("coincident surfaces go to the primitive listed last", "[reference][ties]") {
    Scene scene;
    for (int i = 0; i < 5; ++i) {
        // Five identical cubes, then a sphere elsewhere, so that the BVH splits them.
        addInstance(scene, PrimitiveType::Cube, Affine::translation({0, 0, 0}), addMaterial(scene, diffuseMaterial({1, 1, 1})));
    }
    addInstance(scene, PrimitiveType::Sphere, Affine::translation({9, 0, 0}), 0);
    for (reference::SceneSearch search : {reference::SceneSearch::Bvh, reference::SceneSearch::BruteForce}) {
        reference::SceneIntersector intersector(scene, search);
        for (const Vec3& direction : {Vec3{0, 0, -1}, Vec3{0.1, -0.2, -1}, Vec3{-1, 0.05, 0.02}}) {
            auto hit = intersector.closestHit(Vec3{0, 0, 0} - 4 * direction, direction, 0, INFINITY);
            REQUIRE(hit);
            CHECK(hit->primitive == 4);
        }
    }
}

TEST_CASE("threads, progress and cancelling", "[reference]") {
    const Scene scene = randomScene(60);
    const RenderSettings settings = smallCourseSettings();
    ReferenceRenderOptions one, four;
    one.threads = 1;
    four.threads = 4;
    std::atomic<int> calls{0};
    std::atomic<double> last{0};
    four.progress = [&](double fraction) {
        ++calls;
        double seen = last.load();
        while (fraction > seen && !last.compare_exchange_weak(seen, fraction)) {}
    };
    RayCounts oneCounts, fourCounts;
    Image a = renderReference(scene, settings, one, &oneCounts);
    Image b = renderReference(scene, settings, four, &fourCounts);
    REQUIRE(a.rgb == b.rgb);
    REQUIRE(oneCounts.total() == fourCounts.total());
    REQUIRE(oneCounts.primary >= uint64_t(4 * settings.width * settings.height));
    REQUIRE(calls == settings.height);
    REQUIRE(last == 1.0);

    SECTION("a cancel flag set before the start leaves the image black") {
        std::atomic<bool> cancel{true};
        ReferenceRenderOptions cancelled;
        cancelled.cancel = &cancel;
        RayCounts counts;
        Image image = renderReference(scene, settings, cancelled, &counts);
        REQUIRE(image.width == settings.width);
        REQUIRE(counts.primary == 0);
        REQUIRE(std::all_of(image.rgb.begin(), image.rgb.end(), [](float v) { return v == 0; }));
    }
}

TEST_CASE("scenes with a torus render", "[reference]") {
    Scene scene = onePixelScene();
    scene.sourceFile = "donut.xml";
    addInstance(scene, PrimitiveType::Torus, Affine::identity(), addMaterial(scene, Material{}));
    REQUIRE_NOTHROW(renderReference(scene, onePixelSettings()));
}

TEST_CASE("course antialiasing: sample positions and counts", "[reference][sampling]") {
    std::vector<std::pair<double, double>> positions;
    auto recording = [&](std::function<Vec3(double, double)> color) {
        return [&positions, color](double sx, double sy) {
            positions.emplace_back(sx, sy);
            return color(sx, sy);
        };
    };

    SECTION("a flat pixel: four samples at the quadrant centres") {
        CourseSampleCount count;
        Vec3 c = sampleCourse(recording([](double, double) { return Vec3{0.3, 0.6, 0.9}; }), &count);
        requireColor(c, {0.3, 0.6, 0.9});
        REQUIRE(count.traced == 4);
        REQUIRE(count.used == 4);
        REQUIRE(positions == std::vector<std::pair<double, double>>{{0.25, 0.25}, {0.75, 0.25}, {0.25, 0.75},
                                                                    {0.75, 0.75}});
    }
    SECTION("a difference of exactly 50/255 does not subdivide; a little more does") {
        CourseSampleCount count;
        // 0.25 + kCourseAaContrast is exact in double (the constant is a float), so is the difference.
        sampleCourse([](double sx, double) { return Vec3{sx < 0.5 ? 0.25 : 0.25 + kCourseAaContrast, 0, 0}; }, &count);
        REQUIRE(count.traced == 4);
        sampleCourse([](double sx, double) { return Vec3{0, sx < 0.5 ? 0.4 : 0.597, 0}; }, &count);
        REQUIRE(count.traced == 20);
        REQUIRE(count.used == 16);
    }
    SECTION("only quadrants that differ from a horizontal or vertical neighbour subdivide") {
        CourseSampleCount count;
        // White in the top-left quadrant only: it differs from its right and lower neighbours,
        // which subdivide with it; the bottom-right quadrant differs only from it, diagonally.
        Vec3 c = sampleCourse([](double sx, double sy) { return sx < 0.5 && sy < 0.5 ? Vec3{1, 1, 1} : Vec3{}; },
                              &count);
        REQUIRE(count.traced == 4 + 12);
        REQUIRE(count.used == 1 + 12);
        requireColor(c, {0.25, 0.25, 0.25});
        // A ramp along the diagonal: neighbours differ by 0.15, the diagonal by 0.3: no subdivision.
        sampleCourse([](double sx, double sy) { return Vec3{sx < 0.5 ? 0.0 : 0.15, 0, 0} + Vec3{sy < 0.5 ? 0.0 : 0.15, 0, 0}; },
                     &count);
        REQUIRE(count.traced == 4);
    }
    SECTION("an edge at x = 0.3: the quadrants it crosses go down to level 3") {
        CourseSampleCount count;
        Vec3 c = sampleCourse([](double sx, double) { return sx < 0.3 ? Vec3{} : Vec3{1, 1, 1}; }, &count);
        REQUIRE(count.traced == 4 + 16 + 32);
        REQUIRE(count.used == 8 + 32);
        // Level-3 columns at x = 1/16, 3/16 (black), 5/16, 7/16 (white) on the left half.
        requireColor(c, {0.75, 0.75, 0.75});
    }
    SECTION("busy everywhere: every level subdivides, 64 samples at the centres of an 8×8 grid") {
        CourseSampleCount count;
        sampleCourse(recording([](double sx, double) { return Vec3{sx, 0, 0}; }), &count);  // a ramp
        REQUIRE(count.used == 64);
        REQUIRE(count.traced == 84);
        // Level 1 at odd quarters, level 2 at odd eighths, level 3 at odd sixteenths.
        std::set<std::pair<double, double>> expected;
        for (int n : {4, 8, 16})
            for (int a = 0; a < n / 2; ++a)
                for (int b = 0; b < n / 2; ++b) expected.insert({(2 * a + 1.0) / n, (2 * b + 1.0) / n});
        REQUIRE(std::set<std::pair<double, double>>(positions.begin(), positions.end()) == expected);
        REQUIRE(positions.size() == 84);
    }
    SECTION("samples are clamped to [0, 1] before they are compared and averaged") {
        CourseSampleCount count;
        Vec3 c = sampleCourse([](double sx, double) { return Vec3{sx < 0.5 ? 1.0 : 5.0, -1, 0.5}; }, &count);
        REQUIRE(count.traced == 4);
        requireColor(c, {1, 0, 0.5});
    }
}

TEST_CASE("off and stratified sampling", "[reference][sampling]") {
    SECTION("off: one sample at the centre, unclamped") {
        int calls = 0;
        Vec3 c = sampleCenter([&](double sx, double sy) {
            ++calls;
            REQUIRE(sx == 0.5);
            REQUIRE(sy == 0.5);
            return Vec3{2, 0, 0};
        });
        REQUIRE(calls == 1);
        requireColor(c, {2, 0, 0});
    }
    SECTION("stratified: one jittered sample in each cell of the grid, reproducibly") {
        std::vector<std::pair<double, double>> first, second, otherSeed;
        auto recordInto = [](std::vector<std::pair<double, double>>& into) {
            return [&into](double sx, double sy) {
                into.emplace_back(sx, sy);
                return Vec3{};
            };
        };
        sampleStratified(recordInto(first), 16, 1234, 7);
        sampleStratified(recordInto(second), 16, 1234, 7);
        sampleStratified(recordInto(otherSeed), 16, 1234, 8);
        REQUIRE(first == second);
        REQUIRE(first != otherSeed);
        REQUIRE(first.size() == 16);
        // Each sample lies in the tent-warped image of its cell (the warp is monotonic).
        auto cellLow = [](int cell) { return double(rayTentOffset(float(cell) / 4)); };
        for (int k = 0; k < 16; ++k) {
            INFO("sample " << k);
            REQUIRE((first[k].first >= cellLow(k % 4) && first[k].first <= cellLow(k % 4 + 1)));
            REQUIRE((first[k].second >= cellLow(k / 4) && first[k].second <= cellLow(k / 4 + 1)));
        }
    }
    SECTION("stratified: a count that is not a square rounds down to one; samples are clamped") {
        int calls = 0;
        Vec3 c = sampleStratified([&](double sx, double sy) {
            ++calls;
            REQUIRE((sx > -0.5 && sx < 1.5 && sy > -0.5 && sy < 1.5));  // the tent's support
            return Vec3{sx < 0.5 ? 3.0 : 0.0, -1, 0.5};
        }, 8, 0, 0);
        REQUIRE(calls == 4);
        requireColor(c, {0.5, 0, 0.5});  // columns 0 and 1 of 2 fall on either side of 0.5
        REQUIRE(stratifiedGridSide(0) == 1);
        REQUIRE(stratifiedGridSide(15) == 3);
        REQUIRE(stratifiedGridSide(16) == 4);
    }
    SECTION("stratified: the jitter is the kernel's, sampleRandom(pixel, cell, 0 | 1, seed)") {
        double sx, sy;
        stratifiedOffset(5, 4, 1234, 7, sx, sy);
        REQUIRE(sx == rayTentOffset(float((1 + sampleRandom(1234, 5, 0, 7)) / 4)));
        REQUIRE(sy == rayTentOffset(float((1 + sampleRandom(1234, 5, 1, 7)) / 4)));
    }
    SECTION("the tent filter: symmetric about the centre, radius one pixel, 3/4 of it inside") {
        CHECK(rayTentOffset(0.5f) == 0.5f);
        CHECK(rayTentOffset(0.0f) == Approx(-0.5));
        CHECK(rayTentOffset(0.125f) == Approx(0.0));  // the tent's CDF at -0.5 is 1/8
        CHECK(rayTentOffset(0.875f) == Approx(1.0));
        int inside = 0;
        const int n = 4096;
        for (int k = 0; k < n; ++k) {
            float offset = rayTentOffset((float(k) + 0.5f) / n);
            CHECK((offset > -0.5f && offset < 1.5f));
            inside += offset >= 0.0f && offset < 1.0f;
        }
        CHECK(double(inside) / n == Approx(0.75).margin(0.001));
    }
    SECTION("a whole stratified render is the same twice, and changes with the seed") {
        const Scene scene = randomScene(30);
        RenderSettings settings = smallCourseSettings();
        settings.antialias = AntialiasMode::Stratified;
        settings.samples = 4;
        Image a = renderReference(scene, settings);
        Image b = renderReference(scene, settings);
        settings.seed = 99;
        Image c = renderReference(scene, settings);
        REQUIRE(a.rgb == b.rgb);
        REQUIRE(a.rgb != c.rgb);
    }
}

TEST_CASE("the counter-based random numbers are pinned (the kernel draws the same)", "[reference][sampling]") {
    REQUIRE(rayHash(0) == 129708002u);
    REQUIRE(rayHash(1) == 2831084092u);
    REQUIRE(rayHash(123456789) == 4272394698u);
    // rayHash(seed ^ rayHash(dimension ^ rayHash(sample ^ rayHash(pixel)))), top 24 bits.
    REQUIRE(sampleRandom(0, 0, 0, 0) == (2368882721u >> 8) / 16777216.0);
    REQUIRE(sampleRandom(5, 7, 1, 11) == (2097168874u >> 8) / 16777216.0);
    REQUIRE(sampleRandom(1234, 15, 0, 7) == 1916490 / 16777216.0);
}
