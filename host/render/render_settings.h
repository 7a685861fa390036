// What to render and how: the options both renderers take, set from the command line.
#pragma once

#include <cstdint>

#include "shared_types.h"

namespace ray {

enum class AntialiasMode {
    Off,         // one sample at the pixel centre
    Course,      // the course's deterministic adaptive subdivision (SPEC §3)
    Stratified,  // jittered stratified samples, --samples N
    Adaptive,    // stochastic refinement where neighbouring samples differ
};

// Course: bilinear with texel corners at integer coordinates, as the course's renders
// (SPEC §5); Bilinear and Trilinear put texel centres there.
enum class TextureFilter { Nearest, Bilinear, Trilinear, Course };

// Depth of field, for a camera with an aperture (SPEC §3). Course (the default): each
// sample is the mean of the clamped colors of 25 rays from a 5×5 grid of lens points
// spaced aperture/2, aimed where the pinhole ray meets the plane at depth focallength
// along the look axis, as the course renders it. Disk: one lens point a sample, uniform on
// the lens disk (random dimensions 2, 3 of the sample), aimed at distance focallength
// along the pinhole ray; a smooth blur under a stochastic --aa with many samples.
enum class DofMode { Course, Disk };

// The defaults here are the only ones: the settings table (render/settings_table.h), which
// gives each member a front end sets its name, range or choices and help, reads them off
// RenderSettings{} for --help, the viewer and the API's checks.
struct RenderSettings {
    int width = 1024;
    int height = 768;
    int maxDepth = 4;  // bounces after the camera ray; 0 = no reflection or refraction
    AntialiasMode antialias = AntialiasMode::Course;
    int samples = 16;  // per pixel, for the stochastic modes
    // A reflected or refracted branch stops when its accumulated weight is below this in
    // every channel (SPEC §4).
    double weightThreshold = 1.0 / 256.0;
    bool shadows = true;
    bool reflections = true;
    bool refraction = true;
    bool textures = true;
    bool depthOfField = true;
    DofMode dofMode = DofMode::Course;  // --dof
    // --fresnel (SPEC §4, off by default): the surfaces of transparent objects weight their
    // reflected and transmitted branches by the exact Fresnel reflectance R, ks·Or·R and
    // kt·Ot·(1 − R), and split a ray leaving the object into R inside and 1 − R out
    // (docs/conventions.md, refraction). Needs refraction on.
    bool fresnel = false;
    // --course-meshes (off by default): the course solution's mesh bug
    // (docs/conventions.md, meshes): a mesh hit's distance is t_obj = t·|M⁻¹d| (along the
    // normalized object-space direction), compared with the other primitives' world t for
    // the nearest hit and placing the hit point at origin + t_obj·d; meshes are shaded
    // with face normals. Shadow rays keep world t.
    bool courseMeshes = false;
    TextureFilter textureFilter = TextureFilter::Nearest;
    uint32_t seed = 0;
    // Point samples per area light, on a k×k jittered grid (k = floor(√areaSamples)):
    // 16 keeps the course's area-light penumbras smooth under course antialiasing.
    int areaSamples = 16;
    // Motion blur: camera sample k of a pixel sees the scene at time
    // t = shutter · sampleRandom(pixel, k, 4, seed) (random.h), when every moving instance
    // is translated by t·motion (scene.h PrimitiveInstance::motion). 1: the whole motion;
    // 0: the scene at rest. Every antialiasing mode draws the time per camera sample.
    double shutter = 1;
};

// Limits on what the command line and the API accept (the settings table's ranges).
constexpr int kMaxImageSide = 16384;
constexpr int kMaxDepth = 64;
constexpr int kMaxSamples = 4096;
constexpr int kMaxAreaSamples = 1024;  // 32 × 32: the random dimensions reserved per area light (optics.h)

// k = floor(√areaSamples), at least 1: the side of an area light's sample grid.
int areaLightGridSide(const RenderSettings& settings);

// The antialiasing thresholds, shared with the kernel (cl/shared_types.h), as the float
// values the kernel compares against.
constexpr double kCourseAaContrast = RAY_COURSE_AA_CONTRAST;  // neighbours differing by more subdivide
constexpr int kCourseAaMaxLevel = 3;  // levels 1..3: at most 4³ = 64 samples a pixel
constexpr double kAdaptiveContrast = RAY_ADAPTIVE_CONTRAST;

}  // namespace ray
