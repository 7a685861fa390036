// Ray intersection of the unit primitives (SPEC §2), their texture coordinates (SPEC §5),
// texel lookup, and the reference BVH.
#include <catch2/catch.hpp>

#include <cmath>

#include "reference/reference_bvh.h"
#include "reference/shapes.h"
#include "reference/texture_sampling.h"

using namespace ray;

namespace {

constexpr double kEps = 1e-12;

void requireVec(const Vec3& actual, const Vec3& expected, double eps = kEps) {
    INFO("actual (" << actual.x << ", " << actual.y << ", " << actual.z << "), expected (" << expected.x << ", "
                    << expected.y << ", " << expected.z << ")");
    REQUIRE(actual.x == Approx(expected.x).margin(eps));
    REQUIRE(actual.y == Approx(expected.y).margin(eps));
    REQUIRE(actual.z == Approx(expected.z).margin(eps));
}

void requireHit(const std::optional<ShapeHit>& hit, double t, const Vec3& normal) {
    REQUIRE(hit);
    REQUIRE(hit->t == Approx(t).margin(kEps));
    requireVec(hit->normal, normal);
}

void requireUV(const std::optional<ShapeHit>& hit, double u, double v) {
    REQUIRE(hit);
    REQUIRE(hit->uv.u == Approx(u).margin(1e-9));
    REQUIRE(hit->uv.v == Approx(v).margin(1e-9));
}

const double kSqrt5 = std::sqrt(5.0);

}  // namespace

TEST_CASE("cube: hits on every face, from outside and inside", "[shapes]") {
    requireHit(intersectCube({0, 0, 5}, {0, 0, -1}, 0, INFINITY), 4.5, {0, 0, 1});
    requireHit(intersectCube({0, 0, -5}, {0, 0, 1}, 0, INFINITY), 4.5, {0, 0, -1});
    requireHit(intersectCube({5, 0.1, 0.2}, {-1, 0, 0}, 0, INFINITY), 4.5, {1, 0, 0});
    requireHit(intersectCube({-5, 0.1, 0.2}, {1, 0, 0}, 0, INFINITY), 4.5, {-1, 0, 0});
    requireHit(intersectCube({0.1, 5, 0.2}, {0, -1, 0}, 0, INFINITY), 4.5, {0, 1, 0});
    requireHit(intersectCube({0.1, -5, 0.2}, {0, 1, 0}, 0, INFINITY), 4.5, {0, -1, 0});

    SECTION("from inside, the hit is where the ray leaves, with the outward normal") {
        requireHit(intersectCube({0, 0, 0}, {1, 0, 0}, 0, INFINITY), 0.5, {1, 0, 0});
        requireHit(intersectCube({0.2, 0, 0}, {0, -1, 0}, 0, INFINITY), 0.5, {0, -1, 0});
    }
    SECTION("an unnormalized direction keeps t in its own units") {
        requireHit(intersectCube({0, 0, 5}, {0, 0, -2}, 0, INFINITY), 2.25, {0, 0, 1});
    }
    SECTION("a diagonal ray enters through the face it crosses first") {
        requireHit(intersectCube({-2, 0.1, -0.6}, {1, 0, 0.3}, 0, INFINITY), 1.5, {-1, 0, 0});
    }
    SECTION("misses") {
        REQUIRE_FALSE(intersectCube({2, 0, 5}, {0, 0, -1}, 0, INFINITY));
        REQUIRE_FALSE(intersectCube({0, 0, 5}, {0, 0, 1}, 0, INFINITY));        // pointing away
        REQUIRE_FALSE(intersectCube({0, 0.5 + 1e-9, 5}, {0, 0, -1}, 0, INFINITY));  // just above
        REQUIRE_FALSE(intersectCube({-3, 0, 3}, {1, 0, -0.1}, 0, INFINITY));   // passes beside it
    }
    SECTION("grazing along a face counts as a hit (faces are closed)") {
        requireHit(intersectCube({-5, 0.5, 0}, {1, 0, 0}, 0, INFINITY), 4.5, {-1, 0, 0});
    }
    SECTION("tMin and tMax bound the hit") {
        REQUIRE_FALSE(intersectCube({0, 0, 5}, {0, 0, -1}, 0, 4.4));
        requireHit(intersectCube({0, 0, 5}, {0, 0, -1}, 4.6, INFINITY), 5.5, {0, 0, -1});
        REQUIRE_FALSE(intersectCube({0, 0, 5}, {0, 0, -1}, 5.6, INFINITY));
    }
}

TEST_CASE("sphere: hits, misses, tangents, inside", "[shapes]") {
    requireHit(intersectSphere({0, 0, 5}, {0, 0, -1}, 0, INFINITY), 4.5, {0, 0, 1});
    requireHit(intersectSphere({0, 0, 5}, {0, 0, -4}, 0, INFINITY), 1.125, {0, 0, 1});
    requireHit(intersectSphere({0, -3, 0}, {0, 1, 0}, 0, INFINITY), 2.5, {0, -1, 0});
    // Through (0.3, 0.4, 0), where the normal is (0.6, 0.8, 0).
    requireHit(intersectSphere({5, 0.4, 0}, {-1, 0, 0}, 0, INFINITY), 4.7, {0.6, 0.8, 0});

    SECTION("from inside") {
        requireHit(intersectSphere({0, 0, 0}, {0, 1, 0}, 0, INFINITY), 0.5, {0, 1, 0});
        requireHit(intersectSphere({0, 0, 5}, {0, 0, -1}, 4.6, INFINITY), 5.5, {0, 0, -1});
    }
    SECTION("a tangent ray touches, one a hair outside misses") {
        requireHit(intersectSphere({0.5, 0, 5}, {0, 0, -1}, 0, INFINITY), 5, {1, 0, 0});
        REQUIRE_FALSE(intersectSphere({0.5 + 1e-9, 0, 5}, {0, 0, -1}, 0, INFINITY));
    }
    SECTION("misses") {
        REQUIRE_FALSE(intersectSphere({0, 0, 5}, {0, 0, 1}, 0, INFINITY));
        REQUIRE_FALSE(intersectSphere({1, 1, 5}, {0, 0, -1}, 0, INFINITY));
        REQUIRE_FALSE(intersectSphere({0, 0, 5}, {0, 0, -1}, 0, 4));
    }
    SECTION("a tiny sphere far away (object space: far and with a short direction)") {
        // A sphere of radius 1e-5 seen from 1000 units: in object space the origin is
        // 1e8 away. The near root must still be accurate.
        auto hit = intersectSphere({0.3, 0, 1e8}, {0, 0, -1e5}, 0, INFINITY);
        REQUIRE(hit);
        REQUIRE(hit->t == Approx((1e8 - 0.4) / 1e5).epsilon(1e-12));
        requireVec(hit->normal, {0.6, 0, 0.8}, 1e-6);
    }
}

TEST_CASE("cylinder: side, caps, rims and inside", "[shapes]") {
    requireHit(intersectCylinder({5, 0.2, 0}, {-1, 0, 0}, 0, INFINITY), 4.5, {1, 0, 0});
    requireHit(intersectCylinder({0, 0.2, -5}, {0, 0, 1}, 0, INFINITY), 4.5, {0, 0, -1});
    requireHit(intersectCylinder({0.2, 5, -0.1}, {0, -1, 0}, 0, INFINITY), 4.5, {0, 1, 0});
    requireHit(intersectCylinder({0.2, -5, -0.1}, {0, 1, 0}, 0, INFINITY), 4.5, {0, -1, 0});

    SECTION("a slanted ray onto a cap") {
        requireHit(intersectCylinder({0, 2, 0.3}, {0, -1, -0.1}, 0, INFINITY), 1.5, {0, 1, 0});
    }
    SECTION("from inside") {
        requireHit(intersectCylinder({0, 0, 0}, {1, 0, 0}, 0, INFINITY), 0.5, {1, 0, 0});
        requireHit(intersectCylinder({0, 0, 0}, {0, 1, 0}, 0, INFINITY), 0.5, {0, 1, 0});
        requireHit(intersectCylinder({0, 0, 0}, {0, -1, 0}, 0, INFINITY), 0.5, {0, -1, 0});
    }
    SECTION("misses") {
        REQUIRE_FALSE(intersectCylinder({5, 0.6, 0}, {-1, 0, 0}, 0, INFINITY));   // above
        REQUIRE_FALSE(intersectCylinder({0.6, 5, 0}, {0, -1, 0}, 0, INFINITY));   // parallel, outside
        REQUIRE_FALSE(intersectCylinder({5, 0, 0.6}, {-1, 0, 0}, 0, INFINITY));   // beside
    }
    SECTION("grazing the side, and down the rim, counts as a hit") {
        requireHit(intersectCylinder({5, 0, 0.5}, {-1, 0, 0}, 0, INFINITY), 5, {0, 0, 1});
        requireHit(intersectCylinder({0.5, 5, 0}, {0, -1, 0}, 0, INFINITY), 4.5, {0, 1, 0});
    }
}

TEST_CASE("cone: side, apex, base cap and inside", "[shapes]") {
    // At y = 0 the radius is 0.25; the side's normal is ∝ (2·radial, 1).
    requireHit(intersectCone({0, 0, 5}, {0, 0, -1}, 0, INFINITY), 4.75, Vec3{0, 1, 2} / kSqrt5);
    requireHit(intersectCone({0.1, -5, 0.2}, {0, 1, 0}, 0, INFINITY), 4.5, {0, -1, 0});

    SECTION("straight down the axis onto the apex") {
        requireHit(intersectCone({0, 5, 0}, {0, -1, 0}, 0, INFINITY), 4.5, {0, 1, 0});
    }
    SECTION("straight down beside the apex onto the side") {
        // Radius 0.3 at y = −0.1.
        requireHit(intersectCone({0.3, 5, 0}, {0, -1, 0}, 0, INFINITY), 5.1, Vec3{2, 1, 0} / kSqrt5);
    }
    SECTION("a ray parallel to a generating line (the linear case)") {
        requireHit(intersectCone({-0.6, 0.5, 0}, {1, -2, 0}, 0, INFINITY), 0.3, Vec3{-2, 1, 0} / kSqrt5);
    }
    SECTION("from inside") {
        requireHit(intersectCone({0, -0.25, 0}, {1, 0, 0}, 0, INFINITY), 0.375, Vec3{2, 1, 0} / kSqrt5);
        requireHit(intersectCone({0, -0.25, 0}, {0, -1, 0}, 0, INFINITY), 0.25, {0, -1, 0});
    }
    SECTION("misses, including the mirrored half above the apex") {
        REQUIRE_FALSE(intersectCone({0.6, 5, 0}, {0, -1, 0}, 0, INFINITY));
        REQUIRE_FALSE(intersectCone({5, 0.7, 0}, {-1, 0, 0}, 0, INFINITY));
        REQUIRE_FALSE(intersectCone({5, 0.3, 0.2}, {-1, 0, 0}, 0, INFINITY));  // radius 0.1 there
    }
}

TEST_CASE("texture coordinates of the cube, every face", "[uv]") {
    // A point off centre on each face, with SPEC §5's rule written out.
    const double a = 0.2, b = -0.3;  // the face's two free coordinates
    requireUV(intersectCube({a, b, 5}, {0, 0, -1}, 0, INFINITY), a + 0.5, b + 0.5);     // +z
    requireUV(intersectCube({a, b, -5}, {0, 0, 1}, 0, INFINITY), 0.5 - a, b + 0.5);     // −z
    requireUV(intersectCube({5, b, a}, {-1, 0, 0}, 0, INFINITY), 0.5 - a, b + 0.5);     // +x: u = 0.5 − z
    requireUV(intersectCube({-5, b, a}, {1, 0, 0}, 0, INFINITY), a + 0.5, b + 0.5);     // −x: u = z + 0.5
    requireUV(intersectCube({a, 5, b}, {0, -1, 0}, 0, INFINITY), a + 0.5, 0.5 - b);     // +y: v = 0.5 − z
    requireUV(intersectCube({a, -5, b}, {0, 1, 0}, 0, INFINITY), a + 0.5, b + 0.5);     // −y: v = z + 0.5

    SECTION("u grows to the right and v upwards, as seen from outside each side face") {
        // Seen from +x, right is −z; from −x, right is +z; from −z, right is −x.
        auto left = intersectCube({5, 0, 0.3}, {-1, 0, 0}, 0, INFINITY);
        auto right = intersectCube({5, 0, -0.3}, {-1, 0, 0}, 0, INFINITY);
        REQUIRE(right->uv.u > left->uv.u);
        auto back = intersectCube({-0.3, 0.2, -5}, {0, 0, 1}, 0, INFINITY);
        REQUIRE(back->uv.u == Approx(0.8));
        REQUIRE(back->uv.v == Approx(0.7));
    }
}

TEST_CASE("texture coordinates of the sphere", "[uv]") {
    // u = fract(atan2(−z, x)/2π): 0 at +x, 0.25 at −z, 0.5 at −x, 0.75 at +z.
    requireUV(intersectSphere({0, 0, -5}, {0, 0, 1}, 0, INFINITY), 0.25, 0.5);
    requireUV(intersectSphere({-5, 0, 0}, {1, 0, 0}, 0, INFINITY), 0.5, 0.5);
    requireUV(intersectSphere({0, 0, 5}, {0, 0, -1}, 0, INFINITY), 0.75, 0.5);
    SECTION("poles: v = 0.5 + asin(y/0.5)/π") {
        requireUV(intersectSphere({0, 5, 0}, {0, -1, 0}, 0, INFINITY), 0, 1);
        requireUV(intersectSphere({0, -5, 0}, {0, 1, 0}, 0, INFINITY), 0, 0);
        auto hit = intersectSphere({0, 0.25, 5}, {0, 0, -1}, 0, INFINITY);
        REQUIRE(hit->uv.v == Approx(0.5 + std::asin(0.5) / kPi));
    }
    SECTION("the seam is on the +x side: just below −z side of it u ≈ 0, just on the +z side u ≈ 1") {
        auto towardMinusZ = intersectSphere({5, 0, -1e-6}, {-1, 0, 0}, 0, INFINITY);
        auto towardPlusZ = intersectSphere({5, 0, 1e-6}, {-1, 0, 0}, 0, INFINITY);
        REQUIRE(towardMinusZ->uv.u == Approx(0).margin(1e-5));
        REQUIRE(towardPlusZ->uv.u == Approx(1).margin(1e-5));
        REQUIRE(towardPlusZ->uv.u < 1);
    }
}

TEST_CASE("texture coordinates of the cylinder and the cone", "[uv]") {
    SECTION("cylinder side: u as the sphere's, v = y + 0.5") {
        requireUV(intersectCylinder({0, 0.3, -5}, {0, 0, 1}, 0, INFINITY), 0.25, 0.8);
        requireUV(intersectCylinder({0, -0.4, 5}, {0, 0, -1}, 0, INFINITY), 0.75, 0.1);
    }
    SECTION("cylinder caps: as the cube's ±y faces") {
        requireUV(intersectCylinder({0.2, 5, -0.1}, {0, -1, 0}, 0, INFINITY), 0.7, 0.6);
        requireUV(intersectCylinder({0.2, -5, -0.1}, {0, 1, 0}, 0, INFINITY), 0.7, 0.4);
    }
    SECTION("cone side and base cap") {
        requireUV(intersectCone({-5, 0, 0}, {1, 0, 0}, 0, INFINITY), 0.5, 0.5);
        requireUV(intersectCone({0, -0.3, -5}, {0, 0, 1}, 0, INFINITY), 0.25, 0.2);
        requireUV(intersectCone({0.1, -5, 0.2}, {0, 1, 0}, 0, INFINITY), 0.6, 0.7);
    }
}

TEST_CASE("texel lookup: repeats, rows from the top, clamping", "[uv]") {
    // A 4×2 texture whose texel (x, y) has color (x, y, 0).
    Image texture(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) texture.set(x, y, {double(x), double(y), 0});

    requireVec(sampleNearest(texture, 0.1, 0.9, 1, 1), {0, 0, 0});  // top left
    requireVec(sampleNearest(texture, 0.9, 0.1, 1, 1), {3, 1, 0});  // bottom right
    requireVec(sampleNearest(texture, 0.3, 0.6, 1, 1), {1, 0, 0});
    SECTION("repeats tile the texture") {
        requireVec(sampleNearest(texture, 0.3, 0.1, 2, 1), {2, 1, 0});   // s = 0.6
        requireVec(sampleNearest(texture, 0.6, 0.3, 2, 2), {0, 0, 0});   // s = 0.2, t = 0.6: row floor(0.4·2)
    }
    SECTION("u = v = 1 wrap to s = t = 0 (fract), and rows stay in range") {
        requireVec(sampleNearest(texture, 1, 1, 1, 1), {0, 1, 0});
        requireVec(sampleNearest(texture, 0, 0, 1, 1), {0, 1, 0});
        requireVec(sampleNearest(texture, -0.1, 0.5, 1, 1), {3, 1, 0});  // s = 0.9, row floor(1) = 1
    }
    SECTION("bilinear: texel centres give the texel, midpoints the mean, edges wrap") {
        requireVec(sampleBilinear(texture, 0.375, 0.75, 1, 1), {1, 0, 0});
        requireVec(sampleBilinear(texture, 0.5, 0.75, 1, 1), {1.5, 0, 0});
        requireVec(sampleBilinear(texture, 0.5, 0.5, 1, 1), {1.5, 0.5, 0});
        requireVec(sampleBilinear(texture, 0.0, 0.75, 1, 1), {1.5, 0, 0});  // between x = 3 and x = 0
    }
}

TEST_CASE("world bounds of instances hold the primitive", "[shapes]") {
    PrimitiveInstance instance;
    instance.objectToWorld = Affine::translation({1, 2, 3}) * Affine::rotation({0, 0, 1}, 45) * Affine::scaling({2, 1, 1});
    instance.worldToObject = instance.objectToWorld.inverse();
    reference::Aabb box = reference::worldBounds(instance);
    // The rotated 2×1 rectangle spans (2 + 1)/√2 across in x and y.
    const double half = 1.5 / std::sqrt(2.0);
    requireVec(box.lo, {1 - half, 2 - half, 2.5}, 1e-6);
    requireVec(box.hi, {1 + half, 2 + half, 3.5}, 1e-6);
}
