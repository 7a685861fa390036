// Constructive solid geometry: combining the spans along a ray (host/reference/csg.h), the
// hits of csg objects, and the loader's program for nested objects.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "kernel_comparison.h"
#include "opencl/kernel_source.h"
#include "reference/csg.h"
#include "reference/reference_bvh.h"
#include "scene/scene_loader.h"
#include "shared_types.h"

using namespace ray;

namespace {

// One span from t0 to t1 on operand `operand`'s surface at both ends.
CsgSpan span(double t0, double t1, int operand) {
    CsgSpan s;
    s.enter.operand = s.exit.operand = operand;
    s.enter.entersOperand = true;
    s.exit.entersOperand = false;
    s.enter.hit.t = t0;
    s.exit.hit.t = t1;
    return s;
}

// The spans as (t0, t1) pairs, for comparing.
std::vector<std::pair<double, double>> times(const CsgSpans& spans) {
    std::vector<std::pair<double, double>> result;
    for (const CsgSpan& s : spans) result.emplace_back(s.enter.hit.t, s.exit.hit.t);
    return result;
}

using Pairs = std::vector<std::pair<double, double>>;

// A unit primitive of `type` scaled by `scale` and moved to `centre`, as a csg operand.
PrimitiveInstance operand(PrimitiveType type, double scale, Vec3 centre, int material) {
    PrimitiveInstance p;
    p.type = type;
    p.objectToWorld = Affine::translation(centre) * Affine::scaling({scale, scale, scale});
    p.worldToObject = Affine::scaling({1 / scale, 1 / scale, 1 / scale}) * Affine::translation(-1 * centre);
    p.material = material;
    return p;
}

// A scene of one csg object: `kind` applied to the given operands, left to right.
Scene csgScene(CsgStepKind kind, const std::vector<PrimitiveInstance>& operands) {
    Scene scene;
    CsgObject object;
    for (size_t i = 0; i < operands.size(); ++i) {
        scene.csgOperands.push_back(operands[i]);
        object.program.push_back({CsgStepKind::Operand, int(i)});
        if (i > 0) object.program.push_back({kind, -1});
    }
    scene.csgObjects.push_back(object);
    return scene;
}

}  // namespace

TEST_CASE("touching operands: a union is one solid, an intersection is empty", "[csg]") {
    CsgSpans a{span(0, 1, 0)}, b{span(1, 2, 1)};
    CsgSpans united = combineCsgSpans(CsgStepKind::Union, a, b);
    CHECK(times(united) == Pairs{{0, 2}});
    CHECK(united[0].enter.operand == 0);
    CHECK(united[0].exit.operand == 1);
    CHECK(combineCsgSpans(CsgStepKind::Intersection, a, b).empty());
    CsgSpans cut = combineCsgSpans(CsgStepKind::Difference, a, b);
    CHECK(times(cut) == Pairs{{0, 1}});
    CHECK(cut[0].exit.operand == 1);  // the face a and b share: b's, written later (SPEC §4)
    CHECK(cut[0].exit.entersOperand);
}

TEST_CASE("coincident faces go to the operand written last, a cut face to the subtracted one", "[csg]") {
    CsgSpans a{span(0, 2, 0)}, b{span(1, 2, 1)}, same{span(0, 2, 1)};
    CsgSpans cut = combineCsgSpans(CsgStepKind::Difference, a, b);
    REQUIRE(times(cut) == Pairs{{0, 1}});
    CHECK(cut[0].exit.operand == 1);  // the inner surface the difference cuts: b's material
    CHECK(cut[0].exit.entersOperand);
    CsgSpans both = combineCsgSpans(CsgStepKind::Intersection, a, same);
    REQUIRE(times(both) == Pairs{{0, 2}});
    CHECK(both[0].enter.operand == 1);
    CHECK(both[0].exit.operand == 1);
    CHECK(combineCsgSpans(CsgStepKind::Difference, a, same).empty());
    CHECK(times(combineCsgSpans(CsgStepKind::Union, a, b)) == Pairs{{0, 2}});
}

TEST_CASE("empty and nested results", "[csg]") {
    CsgSpans a{span(0, 1, 0)}, far{span(3, 4, 1)}, cover{span(-1, 5, 2)}, none;
    CHECK(combineCsgSpans(CsgStepKind::Intersection, a, far).empty());
    CHECK(combineCsgSpans(CsgStepKind::Difference, a, cover).empty());
    CHECK(combineCsgSpans(CsgStepKind::Intersection, a, none).empty());
    CHECK(times(combineCsgSpans(CsgStepKind::Union, none, a)) == Pairs{{0, 1}});
    CHECK(times(combineCsgSpans(CsgStepKind::Difference, a, none)) == Pairs{{0, 1}});
    // (a ∪ far) combined again: cover − (a ∪ far) leaves three pieces.
    CsgSpans united = combineCsgSpans(CsgStepKind::Union, a, far);
    CHECK(times(united) == Pairs{{0, 1}, {3, 4}});
    CsgSpans holes = combineCsgSpans(CsgStepKind::Difference, cover, united);
    CHECK(times(holes) == Pairs{{-1, 0}, {1, 3}, {4, 5}});
    CHECK(holes[1].enter.operand == 0);
    CHECK(holes[1].exit.operand == 1);
    CHECK(times(combineCsgSpans(CsgStepKind::Intersection, holes, CsgSpans{span(0.5, 3.5, 3)})) == Pairs{{1, 3}});
}

TEST_CASE("a ray grazing an operand is never inside it", "[csg]") {
    Scene scene = csgScene(CsgStepKind::Union, {operand(PrimitiveType::Sphere, 1, {0, 0, 0}, 0),
                                                operand(PrimitiveType::Cube, 1, {3, 0, 0}, 1)});
    CHECK(csgOperandSpans(scene, 0, {-5, 0.5, 0}, {1, 0, 0}).empty());  // tangent to the sphere
    // Along the cube's top face the slab test keeps the face: the face is the cube's own
    // boundary, so both renderers see the same closed slab.
    CHECK_FALSE(csgOperandSpans(scene, 1, {-5, 0.5, 0}, {1, 0, 0}).empty());
    CsgSpans through = csgOperandSpans(scene, 0, {-5, 0, 0}, {1, 0, 0});
    REQUIRE(times(through) == Pairs{{4.5, 5.5}});
}

TEST_CASE("a ray starting inside: a difference's cavity is left with the normal along the ray", "[csg]") {
    // A ball of radius 2 with a ball of radius 0.5 cut out at (1, 0, 0); the ray starts at the
    // centre, inside the result, and first meets the cavity.
    Scene scene = csgScene(CsgStepKind::Difference, {operand(PrimitiveType::Sphere, 4, {0, 0, 0}, 0),
                                                     operand(PrimitiveType::Sphere, 1, {1, 0, 0}, 1)});
    CsgSpans spans = evaluateCsg(scene, scene.csgObjects[0], {0, 0, 0}, {1, 0, 0});
    REQUIRE(times(spans).size() == 2);
    CHECK(spans[0].enter.hit.t == Approx(-2));
    CHECK(spans[0].exit.hit.t == Approx(0.5));
    auto hit = intersectCsg(scene, scene.csgObjects[0], {0, 0, 0}, {1, 0, 0}, 1e-9, INFINITY);
    REQUIRE(hit);
    CHECK(hit->operand == 1);  // the cut surface: the subtracted ball's material
    CHECK(hit->local.t == Approx(0.5));
    CHECK(hit->local.normal.x == Approx(1));  // out of the result, into the cavity
    // Beyond the cavity the ray re-enters the result: normal against the ray.
    auto next = intersectCsg(scene, scene.csgObjects[0], {0, 0, 0}, {1, 0, 0}, 0.6, INFINITY);
    REQUIRE(next);
    CHECK(next->local.t == Approx(1.5));
    CHECK(next->local.normal.x == Approx(-1));
    auto last = intersectCsg(scene, scene.csgObjects[0], {0, 0, 0}, {1, 0, 0}, 1.6, INFINITY);
    REQUIRE(last);
    CHECK(last->operand == 0);
    CHECK(last->local.normal.x == Approx(1));  // leaving the big ball
}

TEST_CASE("a lens: entering and leaving the intersection of two balls", "[csg]") {
    Scene scene = csgScene(CsgStepKind::Intersection, {operand(PrimitiveType::Sphere, 2, {0, 0, -0.8}, 0),
                                                       operand(PrimitiveType::Sphere, 2, {0, 0, 0.8}, 1)});
    auto front = intersectCsg(scene, scene.csgObjects[0], {0, 0, 5}, {0, 0, -1}, 1e-9, INFINITY);
    REQUIRE(front);
    CHECK(front->operand == 0);  // the front face belongs to the ball centred behind
    CHECK(front->local.t == Approx(4.8));
    CHECK(front->local.normal.z == Approx(1));
    auto back = intersectCsg(scene, scene.csgObjects[0], {0, 0, 5}, {0, 0, -1}, 4.9, INFINITY);
    REQUIRE(back);
    CHECK(back->operand == 1);
    CHECK(back->local.t == Approx(5.2));
    CHECK(back->local.normal.z == Approx(-1));  // leaving: along the ray
    CHECK_FALSE(intersectCsg(scene, scene.csgObjects[0], {0, 1.5, 5}, {0, 0, -1}, 0, INFINITY));
}

TEST_CASE("nested csg objects flatten to one postfix program, masters place them", "[csg][loader]") {
    const std::string xml = R"(<scenefile>
<object type="tree" name="root">
 <transblock><translate x="2" y="0" z="0"/><object type="master" name="part"/></transblock>
 <transblock><object type="master" name="part"/></transblock>
</object>
<object type="tree" name="part">
 <transblock>
  <object type="csg" operation="difference">
   <transblock><object type="csg" operation="intersection">
     <transblock><object type="primitive" name="cube"/></transblock>
     <transblock><object type="primitive" name="sphere"/></transblock>
   </object></transblock>
   <transblock><scale x="0.3" y="2" z="0.3"/>
     <object type="primitive" name="cylinder"/><object type="primitive" name="cone"/></transblock>
  </object>
 </transblock>
</object>
</scenefile>)";
    LoadOptions options;
    options.warn = [](const std::string&) {};
    Scene scene = loadSceneFromText(xml, "test.xml", options);
    REQUIRE(scene.primitives.size() == 2);
    REQUIRE(scene.csgObjects.size() == 2);
    CHECK(scene.csgOperands.size() == 8);
    using K = CsgStepKind;
    std::vector<K> kinds;
    for (const CsgStep& s : scene.csgObjects[0].program) kinds.push_back(s.kind);
    CHECK(kinds == std::vector<K>{K::Operand, K::Operand, K::Intersection, K::Operand, K::Operand, K::Union,
                                  K::Difference});
    CHECK(csgStackDepth(scene.csgObjects[0]) == 3);
    CHECK(scene.primitives[0].type == PrimitiveType::Csg);
    // The csg instance is boxed by its first operand (a difference): the unit cube, moved by 2.
    CHECK(scene.primitives[0].objectLo.x == Approx(1.5));
    CHECK(scene.primitives[0].objectHi.x == Approx(2.5));
    // Both renderers find it through their BVH: the reference's.
    reference::SceneIntersector intersector(scene);
    // From inside the hole along the axis, out through the wall the cylinder cut.
    auto hit = intersector.closestHit({2, 0, 0}, {0, 0, 1}, 1e-9, INFINITY);
    REQUIRE(hit);
    CHECK(hit->primitive == 0);
    CHECK(hit->local.t == Approx(0.15));
    REQUIRE(hit->csgOperand >= 0);
    CHECK(scene.csgOperands[size_t(hit->csgOperand)].type == PrimitiveType::Cylinder);
    CHECK(hit->local.normal.z == Approx(-1));  // into the hole: out of the result, against the ray
    CHECK_FALSE(intersector.closestHit({2, 5, 0}, {0, -1, 0}, 1e-9, INFINITY));  // down the hole
}

namespace {

// A small scene around `objects` (inside the root tree), lit and seen from the front-right.
std::string csgTestScene(const std::string& objects) {
    return R"(<scenefile>
<cameradata><pos x="2.5" y="2" z="3.5"/><focus x="0" y="0" z="0"/><up x="0" y="1" z="0"/><heightangle v="45"/></cameradata>
<lightdata><id v="0"/><type v="point"/><color r="1" g="1" b="1"/><position x="3" y="4" z="3"/></lightdata>
<object type="tree" name="root">
 <transblock><translate x="0" y="-0.8" z="0"/><scale x="6" y="0.1" z="6"/>
  <object type="primitive" name="cube"><diffuse r="0.8" g="0.8" b="0.8"/><reflective r="0.3" g="0.3" b="0.3"/></object>
 </transblock>
)" + objects + R"(
</object>
</scenefile>)";
}

}  // namespace

// Beyond the bundled scenes (which the kernel-versus-host test of every bundled scene covers):
// a moving csg object, and operands with coincident faces, where float and double must
// still agree on which surface is whose.
TEST_CASE("kernel matches host on moving csg and coincident faces", "[csg][kernel][kvh]") {
    auto device = test::cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    const std::string red = R"(<diffuse r="0.9" g="0.2" b="0.1"/><specular r="0.5" g="0.5" b="0.5"/><shininess v="20"/>)";
    const std::string blue = R"(<diffuse r="0.1" g="0.3" b="0.9"/>)";
    const std::string moving = csgTestScene(R"(<transblock><motion x="0.6" y="0" z="0"/>
  <object type="csg" operation="difference">
   <transblock><object type="primitive" name="sphere">)" + red + R"(</object></transblock>
   <transblock><translate x="0.3" y="0.3" z="0.3"/><scale x="0.6" y="0.6" z="0.6"/><object type="primitive" name="cube">)" +
                                            blue + R"(</object></transblock>
  </object></transblock>)");
    const std::string coincident = csgTestScene(R"(<transblock><object type="csg" operation="difference">
   <transblock><object type="primitive" name="cube">)" + red + R"(</object></transblock>
   <transblock><translate x="0.25" y="0.25" z="0"/><scale x="0.5" y="0.5" z="1"/><object type="primitive" name="cube">)" +
                                                blue + R"(</object></transblock>
  </object></transblock>
  <transblock><translate x="-1.2" y="0" z="0"/><object type="csg" operation="union">
   <transblock><translate x="0" y="0" z="-0.25"/><scale x="1" y="1" z="0.5"/><object type="primitive" name="cube">)" +
                                                red + R"(</object></transblock>
   <transblock><translate x="0" y="0" z="0.25"/><scale x="1" y="1" z="0.5"/><object type="primitive" name="cube">)" +
                                                blue + R"(</object></transblock>
  </object></transblock>)");
    LoadOptions options;
    options.warn = [](const std::string&) {};
    RenderSettings blurred = test::settingsFromOptions("--aa stratified --samples 4", 64, 48);
    test::compareKernelWithHost(*device, loadSceneFromText(moving, "moving.xml", options), blurred, "csg_moving");
    RenderSettings plain = test::settingsFromOptions("--aa off", 96, 72);
    test::compareKernelWithHost(*device, loadSceneFromText(coincident, "coincident.xml", options), plain,
                                "csg_coincident");
}

TEST_CASE("slivers of rounding between nearly coincident faces are dropped", "[csg]") {
    CsgSpans a{span(0, 2, 0)}, b{span(1, 2 - 1e-7, 1)};
    CHECK(times(combineCsgSpans(CsgStepKind::Difference, a, b)) == Pairs{{0, 1}});  // no film at t = 2
    CsgSpans left{span(0, 1, 0)}, right{span(1 + 1e-7, 2, 1)};
    CHECK(times(combineCsgSpans(CsgStepKind::Union, left, right)) == Pairs{{0, 2}});  // no gap at t = 1
    CHECK(combineCsgSpans(CsgStepKind::Intersection, CsgSpans{span(0, 1 + 1e-7, 0)}, CsgSpans{span(1, 2, 1)}).empty());
    // A thin wall that is geometry stays: 1e-3 of the distance.
    CHECK(times(combineCsgSpans(CsgStepKind::Difference, a, CsgSpans{span(1, 1.999, 1)})) ==
          Pairs{{0, 1}, {1.999, 2}});
}

namespace {

// The kernel's combination (cl/geometry/csg.cl csgCombine) run on a postfix program of operand spans
// given as numbers, with the stack walk of intersectCsg, one program a work-item: the
// sources up to cl/geometry/csg.cl (all it uses) and this kernel, which writes the final list.
constexpr int kProgramSteps = 2 * kCsgMaxOperands;  // RAY_CSG_BOUNDARIES: room for every step, every result
const char* const kCombineTestKernel = R"(
__kernel void csgProgramTest(__global const int* kinds, __global const float2* spans, __global const int* steps,
                             __global int* counts, __global float* outTimes, __global uchar* outCodes) {
    const int program = get_global_id(0), base = program * RAY_CSG_BOUNDARIES;
    float times[RAY_CSG_BOUNDARIES];
    uchar codes[RAY_CSG_BOUNDARIES];
    int start[RAY_CSG_MAX_STACK + 1];
    int top = 0;
    start[0] = 0;
    for (int step = 0; step < steps[program]; ++step) {
        int kind = kinds[base + step];
        if (kind == 0) {
            int at = start[top], count = 0;
            float2 span = spans[base + step];
            if (span.y > span.x) { /* as csgOperandBoundaries */
                times[at] = span.x;
                codes[at] = (uchar)(step * 2);
                times[at + 1] = span.y;
                codes[at + 1] = (uchar)(step * 2 + 1);
                count = 2;
            }
            start[top + 1] = at + count;
            ++top;
            continue;
        }
        int a = start[top - 2];
        start[top - 1] = a + csgCombine(kind, start[top - 1] - a, start[top] - start[top - 1], times + a, codes + a);
        --top;
    }
    counts[program] = start[1];
    for (int k = 0; k < start[1]; ++k) {
        outTimes[base + k] = times[k];
        outCodes[base + k] = codes[k];
    }
}
)";

struct RandomCsgProgram {
    std::vector<int> kinds;        // 0: an operand, else RAY_CSG_UNION, _INTERSECTION or _DIFFERENCE
    std::vector<cl_float2> spans;  // an operand's (enter, leave); leave <= enter: no span
};

// Ends on a coarse grid, so that operands touch and share faces, some moved by a sliver
// (about 2e-7 of t, far under kCsgSliver) and some by a thin wall (1e-3, far over it), so
// that float and double decide every sliver alike. Stacks up to kCsgMaxStack deep; half the
// programs are mostly unions of kCsgMaxOperands operands, for long lists.
RandomCsgProgram randomCsgProgram(std::mt19937& random) {
    auto pick = [&](int n) { return int(random() % unsigned(n)); };
    auto end = [&]() {
        float t = float(pick(96) - 16) * 0.25f;
        switch (pick(6)) {
            case 0: return t * (1 + 2e-7f);
            case 1: return t * (1 - 2e-7f);
            case 2: return t + 1e-3f * (std::fabs(t) + 1);
            default: return t;
        }
    };
    RandomCsgProgram p;
    const bool mostlyUnions = pick(2) == 0;  // long lists: many disjoint spans
    const int operands = mostlyUnions ? kCsgMaxOperands : 1 + pick(kCsgMaxOperands);
    int pushed = 0, depth = 0;
    while (pushed < operands || depth > 1) {
        if (pushed < operands && (depth < 2 || (depth < kCsgMaxStack && pick(2) == 0))) {
            float enter = end();
            float leave = pick(8) == 0 ? enter * (1 + 2e-7f) : pick(2) ? enter + float(1 + pick(4)) * 0.25f : end();
            p.kinds.push_back(0);
            p.spans.push_back({{enter, leave}});
            ++pushed, ++depth;
        } else {
            p.kinds.push_back(mostlyUnions && pick(4) ? RAY_CSG_UNION : RAY_CSG_UNION + pick(3));
            p.spans.push_back({{0, 0}});
            --depth;
        }
    }
    return p;
}

// The same program on the host (host/reference/csg.cpp), as (t, code) pairs in the kernel's
// coding: the operand's step · 2 + 1 where the ray leaves it.
std::vector<std::pair<float, int>> hostProgramBoundaries(const RandomCsgProgram& p) {
    std::vector<CsgSpans> stack;
    for (size_t step = 0; step < p.kinds.size(); ++step) {
        if (p.kinds[step] == 0) {
            const cl_float2& s = p.spans[step];
            stack.push_back(s.s[1] > s.s[0] ? CsgSpans{span(s.s[0], s.s[1], int(step))} : CsgSpans{});
            continue;
        }
        CsgStepKind kind = p.kinds[step] == RAY_CSG_UNION          ? CsgStepKind::Union
                           : p.kinds[step] == RAY_CSG_INTERSECTION ? CsgStepKind::Intersection
                                                                   : CsgStepKind::Difference;
        CsgSpans b = std::move(stack.back());
        stack.pop_back();
        stack.back() = combineCsgSpans(kind, stack.back(), b);
    }
    std::vector<std::pair<float, int>> result;
    for (const CsgSpan& s : stack.back())
        for (const CsgBoundary* boundary : {&s.enter, &s.exit})
            result.emplace_back(float(boundary->hit.t), boundary->operand * 2 + (boundary->entersOperand ? 0 : 1));
    return result;
}

}  // namespace

// Deep programs of every operator, with touching and coincident spans and slivers: the
// kernel's in-place combination must keep exactly the boundaries the host keeps.
TEST_CASE("kernel combines random csg programs exactly as the host", "[csg][kernel]") {
    auto device = test::cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    std::string source;
    for (const KernelSourceFile& file : kernelSourceFiles()) {
        source += std::string("#line 1 \"") + file.name + "\"\n" + file.text + "\n";
        if (std::string(file.name) == "geometry/csg.cl") break;
    }
    source += kCombineTestKernel;
    cl::Context context(device->device);
    cl::Program program(context, source);
    try {
        program.build({device->device}, "-cl-std=CL1.2");
    } catch (const cl::Error&) {
        FAIL(program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device->device));
    }

    constexpr int kPrograms = 4000;
    std::mt19937 random(23);
    std::vector<RandomCsgProgram> programs;
    std::vector<int> kinds(kPrograms * kProgramSteps, 0), steps(kPrograms);
    std::vector<cl_float2> spans(kPrograms * kProgramSteps);
    for (int i = 0; i < kPrograms; ++i) {
        programs.push_back(randomCsgProgram(random));
        steps[i] = int(programs[i].kinds.size());
        std::copy(programs[i].kinds.begin(), programs[i].kinds.end(), kinds.begin() + i * kProgramSteps);
        std::copy(programs[i].spans.begin(), programs[i].spans.end(), spans.begin() + i * kProgramSteps);
    }
    cl::CommandQueue queue(context, device->device);
    auto input = [&](auto& v) {
        return cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(v[0]), v.data());
    };
    cl::Buffer kindsBuffer = input(kinds), spansBuffer = input(spans), stepsBuffer = input(steps);
    cl::Buffer countsBuffer(context, CL_MEM_WRITE_ONLY, kPrograms * sizeof(int));
    cl::Buffer timesBuffer(context, CL_MEM_WRITE_ONLY, kPrograms * kProgramSteps * sizeof(float));
    cl::Buffer codesBuffer(context, CL_MEM_WRITE_ONLY, kPrograms * kProgramSteps);
    cl::Kernel kernel(program, "csgProgramTest");
    int arg = 0;
    for (cl::Buffer* b : {&kindsBuffer, &spansBuffer, &stepsBuffer, &countsBuffer, &timesBuffer, &codesBuffer})
        kernel.setArg(arg++, *b);
    queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(kPrograms));
    std::vector<int> counts(kPrograms);
    std::vector<float> times(kPrograms * kProgramSteps);
    std::vector<cl_uchar> codes(kPrograms * kProgramSteps);
    queue.enqueueReadBuffer(countsBuffer, CL_TRUE, 0, counts.size() * sizeof(int), counts.data());
    queue.enqueueReadBuffer(timesBuffer, CL_TRUE, 0, times.size() * sizeof(float), times.data());
    queue.enqueueReadBuffer(codesBuffer, CL_TRUE, 0, codes.size(), codes.data());

    int longest = 0, mismatches = 0;
    for (int i = 0; i < kPrograms && mismatches < 5; ++i) {
        std::vector<std::pair<float, int>> kernelBoundaries;
        for (int k = 0; k < counts[i]; ++k)
            kernelBoundaries.emplace_back(times[i * kProgramSteps + k], codes[i * kProgramSteps + k]);
        longest = std::max(longest, counts[i]);
        if (kernelBoundaries == hostProgramBoundaries(programs[i])) continue;
        ++mismatches;
        UNSCOPED_INFO("program " << i << " of " << steps[i] << " steps: the kernel keeps " << counts[i]
                                 << " boundaries, the host " << hostProgramBoundaries(programs[i]).size());
    }
    INFO("longest result: " << longest << " boundaries");
    CHECK(mismatches == 0);
    CHECK(longest >= 16);  // the programs reach long lists
}
