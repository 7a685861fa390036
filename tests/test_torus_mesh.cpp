// The torus (SPEC §2: hits, misses, grazing rays, rays through the hole, normals, UVs),
// the polynomial root isolation under it, and triangle meshes (OBJ loading: polygons, vn,
// vt; the mesh intersector; one mesh stored once for many instances).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "reference/bump_mapping.h"
#include "scene/mesh.h"
#include "reference/mesh_intersector.h"
#include "reference/polynomial.h"
#include "reference/reference_bvh.h"
#include "scene/scene_loader.h"
#include "opencl/scene_packing.h"
#include "reference/shapes.h"
#include "test_support.h"

using namespace ray;

TEST_CASE("polynomial roots: isolated and bisected, close pairs included", "[torus]") {
    // (x − 0.1)(x − 0.3)(x − 0.30001)(x − 2) = 0 on [0, 1]: three roots, two very close.
    const double r[4] = {0.1, 0.3, 0.30001, 2};
    double c[5] = {1, 0, 0, 0, 0};
    for (double root : r) {  // multiply by (x − root)
        for (int i = 4; i >= 1; --i) c[i] = c[i - 1] - root * c[i];
        c[0] = -root * c[0];
    }
    double roots[4];
    REQUIRE(polynomialRootsInInterval(c, 4, 0, 1, roots) == 3);
    CHECK(roots[0] == Approx(0.1).margin(1e-12));
    CHECK(roots[1] == Approx(0.3).margin(1e-9));
    CHECK(roots[2] == Approx(0.30001).margin(1e-9));
}

TEST_CASE("torus: hits from outside, through the hole, grazing and misses", "[torus]") {
    const double R = kTorusMajorRadius, r = kTorusMinorRadius;
    SECTION("along x through the middle: the outer side first, normal outward") {
        auto hit = intersectTorus({5, 0, 0}, {-1, 0, 0}, 0, INFINITY);
        REQUIRE(hit);
        CHECK(hit->t == Approx(5 - (R + r)).margin(1e-9));
        CHECK(hit->normal.x == Approx(1).margin(1e-9));
        CHECK(hit->uv.v == Approx(0).margin(1e-9));  // outer equator
    }
    SECTION("down the axis, through the hole: a miss") {
        CHECK_FALSE(intersectTorus({0, 5, 0}, {0, -1, 0}, 0, INFINITY));
    }
    SECTION("down onto the tube from above: top of the tube, v = 1/4") {
        auto hit = intersectTorus({R, 5, 0}, {0, -1, 0}, 0, INFINITY);
        REQUIRE(hit);
        CHECK(hit->t == Approx(5 - r).margin(1e-9));
        CHECK(hit->normal.y == Approx(1).margin(1e-9));
        CHECK(hit->uv.v == Approx(0.25).margin(1e-9));
        CHECK(hit->uv.u == Approx(0).margin(1e-9));
    }
    SECTION("grazing the top of the tube: just above misses, just below hits near the tangent point") {
        CHECK_FALSE(intersectTorus({-5, r + 1e-7, 0}, {1, 0, 0}, 0, INFINITY));
        auto hit = intersectTorus({-5, r - 1e-7, 0}, {1, 0, 0}, 0, INFINITY);
        REQUIRE(hit);
        CHECK(hit->t == Approx(5 - R).margin(1e-3));
        CHECK(hit->normal.y > 0.99);
    }
    SECTION("a ray through the hole in the ring's plane hits the far inner side") {
        auto hit = intersectTorus({0, 0, 0}, {1, 0, 0}, 0, INFINITY);
        REQUIRE(hit);
        CHECK(hit->t == Approx(R - r).margin(1e-9));
        CHECK(hit->normal.x == Approx(-1).margin(1e-9));
        CHECK(hit->uv.v == Approx(0.5).margin(1e-9));
    }
    SECTION("from a far origin with an unnormalized direction, t keeps its units") {
        auto hit = intersectTorus({1000, 0, 0}, {-2, 0, 0}, 0, INFINITY);
        REQUIRE(hit);
        CHECK(hit->t == Approx((1000 - R - r) / 2).epsilon(1e-12));
    }
    SECTION("from inside the tube, the hit is where the ray leaves") {
        auto hit = intersectTorus({R, 0, 0}, {0, 1, 0}, 0, INFINITY);
        REQUIRE(hit);
        CHECK(hit->t == Approx(r).margin(1e-9));
    }
    SECTION("tMax cuts off hits beyond it") { CHECK_FALSE(intersectTorus({5, 0, 0}, {-1, 0, 0}, 0, 4)); }
}

TEST_CASE("OBJ loading: polygons are triangulated, vn and vt kept", "[mesh]") {
    const char* obj =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
        "vn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\n"  // a quad: two triangles
        "f 1 2 5\n";                   // no vn, no vt
    TriangleMesh mesh = parseObjMesh(obj, "test.obj");
    REQUIRE(mesh.triangles.size() == 3);
    CHECK(mesh.boundsHi.z == 1);
    // The quad's two triangles cover it (area 1); the plain face reads (0, 0) and its face
    // normal. (The quad's vt interpolation is checked through the intersector below.)
    double quadArea = length(cross(mesh.corner(0, 1) - mesh.corner(0, 0), mesh.corner(0, 2) - mesh.corner(0, 0))) / 2 +
                      length(cross(mesh.corner(1, 1) - mesh.corner(1, 0), mesh.corner(1, 2) - mesh.corner(1, 0))) / 2;
    CHECK(quadArea == Approx(1));
    CHECK(mesh.shadingNormal(0, 0.2, 0.2).z == Approx(1));
    CHECK(mesh.texCoordAt(2, 0.3, 0.3)[0] == 0);
    Vec3 face = mesh.shadingNormal(2, 0.3, 0.3);
    CHECK(std::abs(face.y) == Approx(1));

    MeshIntersector intersector(mesh);
    auto hit = intersector.intersect({0.25, 0.75, 5}, {0, 0, -1}, 0, INFINITY);
    REQUIRE(hit);
    CHECK(hit->t == Approx(5));
    CHECK(hit->uv.u == Approx(0.25));
    CHECK(hit->uv.v == Approx(0.75));
    CHECK_FALSE(intersector.intersect({2, 2, 5}, {0, 0, -1}, 0, INFINITY));

    CHECK_THROWS_AS(parseObjMesh("v 0 0 0\n", "empty.obj"), InputError);
}

TEST_CASE("a mesh used by several instances is stored once", "[mesh]") {
    Scene scene = loadScene(test::scenesDir() / "mesh_vase.xml");
    REQUIRE(scene.meshes.size() == 1);
    int instances = 0;
    for (const PrimitiveInstance& p : scene.primitives) instances += p.type == PrimitiveType::Mesh;
    CHECK(instances == 3);
    PackedScene packed = packScene(scene);
    const size_t triangles = scene.meshes[0].triangles.size();
    CHECK(packed.triangles.size() * RAY_TRIANGLES_PER_RECORD >= triangles);
    CHECK(packed.triangles.size() * RAY_TRIANGLES_PER_RECORD < triangles + 2 * packed.triangles.size());
    CHECK(packed.triangleShading.size() == packed.triangles.size() * RAY_TRIANGLES_PER_RECORD);
}

// A lane of a record's float4 row.
static float lane(const gpu::float4& row, int k) { return (&row.x)[k]; }

TEST_CASE("a mesh's leaves are records of up to four triangles, each triangle in one slot, nearly full",
          "[mesh][packing]") {
    Scene scene = loadScene(test::scenesDir() / "mesh_vase.xml");
    REQUIRE(scene.meshes.size() == 1);
    const TriangleMesh& mesh = scene.meshes[0];
    PackedScene packed = packScene(scene);
    // Every leaf link of the mesh's tree: a record's first slot and its triangle count.
    std::vector<int> slotTaken(packed.triangles.size() * RAY_TRIANGLES_PER_RECORD, 0);
    size_t leaves = 0;
    for (size_t n = packed.sceneNodes; n < packed.nodes.size(); ++n) {
        for (int c = 0; c < 4; ++c) {
            const int index = (&packed.nodes[n].index.x)[c], count = (&packed.nodes[n].count.x)[c];
            if (index < 0 || count == 0) continue;
            ++leaves;
            REQUIRE(index % RAY_TRIANGLES_PER_RECORD == 0);
            REQUIRE(count >= 1);
            REQUIRE(count <= RAY_TRIANGLES_PER_RECORD);
            REQUIRE(size_t(index / RAY_TRIANGLES_PER_RECORD) < packed.triangles.size());
            for (int k = 0; k < count; ++k) ++slotTaken[size_t(index + k)];
        }
    }
    CHECK(leaves == packed.triangles.size());  // one record a leaf
    // The slots that leaves name hold the mesh's triangles, each once; the others no triangle.
    std::vector<std::array<float, 9>> stored, expected;
    for (size_t slot = 0; slot < slotTaken.size(); ++slot) {
        REQUIRE(slotTaken[slot] <= 1);
        const gpu::RayTriangle4& r = packed.triangles[slot / RAY_TRIANGLES_PER_RECORD];
        const int k = int(slot % RAY_TRIANGLES_PER_RECORD);
        std::array<float, 9> t = {lane(r.p0x, k), lane(r.p0y, k), lane(r.p0z, k), lane(r.e1x, k), lane(r.e1y, k),
                                  lane(r.e1z, k), lane(r.e2x, k), lane(r.e2y, k), lane(r.e2z, k)};
        if (slotTaken[slot]) stored.push_back(t);
        else CHECK(t == std::array<float, 9>{});  // zero edges: no ray hits an unused slot
    }
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
        const Vec3 p0 = mesh.corner(i, 0), e1 = mesh.corner(i, 1) - p0, e2 = mesh.corner(i, 2) - p0;
        expected.push_back({float(p0[0]), float(p0[1]), float(p0[2]), float(e1[0]), float(e1[1]), float(e1[2]),
                            float(e2[0]), float(e2[1]), float(e2[2])});
    }
    std::sort(stored.begin(), stored.end());
    std::sort(expected.begin(), expected.end());
    CHECK(stored == expected);
    // The tree is built for records (BvhBuildOptions::leafBlock): its leaves are nearly full,
    // where a tree costed a triangle at a time leaves about two triangles a leaf.
    CHECK(double(mesh.triangles.size()) / double(leaves) > 3.0);
}

// A square in the z = 0 plane, facing +z, as two triangles: the left one with its texture
// laid on as seen from the front, the right one mirrored in u (as symmetric models mirror
// half their texture). Bumps that rise with v must tilt the normal against the direction
// in which v grows on both, so B is −(N × T) on the mirrored one.
TEST_CASE("bump mapping on mesh triangles with mirrored texture coordinates", "[mesh][bump]") {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                            "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
                            "f 1/1 2/2 3/3\n"   // u grows along +x, v along +y
                            "f 2/2 4/1 5/3\n";  // u grows along −x (mirrored), v along +y
    TriangleMesh mesh = parseObjMesh(obj, "mirrored.obj");
    REQUIRE(mesh.triangles.size() == 2);
    CHECK(mesh.uvHandedness(0) == 1);
    CHECK(mesh.uvHandedness(1) == -1);
    CHECK(mesh.uTangent(1).x == Approx(-1));

    MeshIntersector intersector(mesh);
    for (double x : {0.2, 1.8}) {
        auto hit = intersector.intersect({x, 0.2, 1}, {0, 0, -1}, 0, INFINITY);
        REQUIRE(hit);
        INFO("x = " << x);
        CHECK(hit->bitangentSign == (x < 1 ? 1 : -1));
        Vec3 bumped = bumpedNormal(hit->normal, hit->tangent, {0, 0.5}, hit->bitangentSign);
        CHECK(bumped.y < -0.5);  // v grows along +y on both triangles: the tilt is toward −y
    }
    // A shading normal facing away from the face reverses the handedness.
    TriangleMesh flipped =
        parseObjMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 -1\nf 1/1/1 2/2/1 3/3/1\n",
                     "flipped.obj");
    auto back = MeshIntersector(flipped).intersect({0.2, 0.2, -1}, {0, 0, 1}, 0, INFINITY);
    REQUIRE(back);
    CHECK(back->bitangentSign == -1);
}

TEST_CASE("bump mapping: a flat map keeps the normal, a ramp tilts it by the documented scale", "[bump]") {
    Image flat(8, 8);
    for (float& c : flat.rgb) c = 0.5f;
    HeightSlope none = heightSlope(flat, 0.3, 0.6, 1, 1);
    CHECK(none.alongU == 0);
    CHECK(none.alongV == 0);

    // A gray ramp rising 0.25 per texel along u, away from the wrap-around seam; with the
    // strength 2 the normal tilts by 45° against the rise.
    Image ramp(8, 1);
    for (int x = 0; x < 8; ++x)
        for (int c = 0; c < 3; ++c) ramp.rgb[size_t(x) * 3 + size_t(c)] = 0.25f * float(x) / 2;
    HeightSlope slope = heightSlope(ramp, 0.5, 0.5, 1, 1);
    CHECK(slope.alongU == Approx(0.125));
    Vec3 n = bumpedNormal({0, 0, 1}, {1, 0, 0}, {0.5, 0});
    CHECK(n.x == Approx(-std::sqrt(0.5)));
    CHECK(n.z == Approx(std::sqrt(0.5)));
    // Along v the tilt goes against B = N × T.
    Vec3 m = bumpedNormal({0, 0, 1}, {1, 0, 0}, {0, 0.5});
    CHECK(m.y == Approx(-std::sqrt(0.5)));
    // No tangent (a mesh without vt): unchanged.
    Vec3 same = bumpedNormal({0, 0, 1}, {}, {0.5, 0.5});
    CHECK(same.z == 1);
    // Tangents follow SPEC §5: the sphere's u grows along (z, 0, −x); the +x face's along −z.
    Vec3 t = objectTangent(PrimitiveType::Sphere, {0.5, 0, 0}, {1, 0, 0});
    CHECK(t.z == Approx(-0.5));
    CHECK(objectTangent(PrimitiveType::Cube, {0.5, 0, 0}, {1, 0, 0}).z == -1);
}

// --course-meshes (docs/conventions.md, meshes): closestHit keys a mesh hit by
// t_obj = t·|M⁻¹d|/|d|. Boxes are pruned by tMax times a bound on t/t_obj, so the BVH must
// find exactly the hits brute force finds; on the course's pdiddy scene (a mesh scaled 3.5
// among trees and a floor) every mesh hit's t is its world t times that factor.
TEST_CASE("course mesh distances: the BVH finds what brute force finds", "[mesh][course-meshes]") {
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent: no pdiddy scene");
        return;
    }
    LoadOptions options;
    options.warn = [](const std::string&) {};
    Scene scene = loadScene(*shared / "cs123" / "scenes" / "pdiddy__cs1230-test_mesh.xml", options);
    reference::SceneIntersector bvh(scene, reference::SceneSearch::Bvh, true);
    reference::SceneIntersector brute(scene, reference::SceneSearch::BruteForce, true);
    reference::SceneIntersector world(scene, reference::SceneSearch::BruteForce, false);
    const reference::Aabb bounds = bvh.sceneBounds();
    std::mt19937 random(5);
    std::uniform_real_distribution<double> unit(0, 1);
    int meshHits = 0, mismatches = 0;
    for (int i = 0; i < 4000; ++i) {
        Vec3 target{bounds.lo.x + unit(random) * (bounds.hi.x - bounds.lo.x),
                    bounds.lo.y + unit(random) * (bounds.hi.y - bounds.lo.y),
                    bounds.lo.z + unit(random) * (bounds.hi.z - bounds.lo.z)};
        Vec3 origin = scene.camera.position, direction = normalize(target - origin);
        auto a = bvh.closestHit(origin, direction, 0, INFINITY);
        auto b = brute.closestHit(origin, direction, 0, INFINITY);
        if (bool(a) != bool(b) || (a && (a->primitive != b->primitive || a->local.t != b->local.t))) ++mismatches;
        if (!b || scene.primitives[size_t(b->primitive)].type != PrimitiveType::Mesh) continue;
        ++meshHits;
        const PrimitiveInstance& mesh = scene.primitives[size_t(b->primitive)];
        double scale = length(mesh.worldToObject.transformVector(direction));
        // The mesh's own world hit, searched in the mesh alone, scaled, is the key.
        auto trueHit = world.closestHit(origin, direction, 0, INFINITY);
        CHECK(scale < 1);  // pdiddy's mesh is scaled up: its key is nearer than its world t
        if (trueHit && trueHit->primitive == b->primitive)
            CHECK(b->local.t == Approx(trueHit->local.t * scale).epsilon(1e-9));
    }
    INFO(meshHits << " of 4000 rays hit the mesh");
    CHECK(mismatches == 0);
    CHECK(meshHits > 50);
}
