// A window into the reference renderer: every step of SPEC §3-§4 for the rays of one pixel.
//
// The reference renderer calls these hooks only when an observer is given (renderReferencePixel);
// a whole-image render passes none, so it pays one null test per step and its images do not
// change. What an observer sees are the very values the renderer adds up: `ray explain`
// (host/explain/) builds its tree from them, so the tree's color is by construction what
// the reference computes.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "reference/shapes.h"

namespace ray {

enum class TraceRayKind { Camera, Reflected, Refracted, TotalInternalReflection };

// Why a reflected or refracted branch was not traced (SPEC §4). NoFresnelShare: with
// --fresnel, a transmitted branch under total internal reflection (R = 1), or a reflected
// one where both sides have the same ior (R = 0).
enum class BranchStop { Disabled, NoCoefficient, NoFresnelShare, DepthLimit, WeightThreshold };

const char* traceRayKindName(TraceRayKind kind);
const char* branchStopName(BranchStop stop);

struct TraceHitInfo {
    int primitive = -1;  // index into Scene::primitives
    double t = 0;
    Vec3 point;
    Vec3 normal;  // world space, unit, facing the ray (bump map applied)
    bool entering = true;
    UV uv;
};

// One light (or one sample of an area light) at one hit point.
struct TraceLightTerm {
    int light = -1;        // index into Scene::lights
    int areaCell = -1;     // area lights: the sample's cell; -1 otherwise
    Vec3 toLight;          // L
    double distance = 0;   // to the light (infinite for directional lights)
    double attenuation = 0;  // f_att (with the spot cone); 0 when not reached
    double nDotL = 0;
    double rDotV = 0;      // max(R·V, 0)
    Vec3 diffuse;          // D·max(N·L, 0)
    Vec3 specular;         // ks·Os·max(R·V, 0)^n
    bool shadowed = false;
    int occluder = -1;     // the nearest primitive between point and light when shadowed
    Vec3 contribution;     // what this term adds to the color
    // Why nothing was added: "" when lit, else "back-facing", "outside the light", "shadowed".
    const char* unlitReason = "";
};

class TraceObserver {
public:
    virtual ~TraceObserver() = default;
    // A camera sample at offsets (sx, sy) within the pixel, sample number k.
    virtual void beginSample(int k, double sx, double sy, double time) = 0;
    virtual void endSample(const Vec3& color) = 0;
    // A ray leaves: depth = bounces so far, weight = its accumulated weight, factor = what
    // its clamped color is multiplied by in its parent (1 for camera rays).
    virtual void beginRay(TraceRayKind kind, const Vec3& origin, const Vec3& direction, int depth,
                          const Vec3& weight, const Vec3& factor) = 0;
    virtual void miss() = 0;
    virtual void hit(const TraceHitInfo& hit) = 0;
    // ka·Oa + Oe, and the diffuse color D (texel: the texture color read, when textured).
    virtual void surfaceTerms(const Vec3& ambient, const Vec3& emissive, const Vec3& diffuseColor, bool textured,
                              const Vec3& texel) = 0;
    virtual void lightTerm(const TraceLightTerm& term) = 0;
    virtual void branchStopped(TraceRayKind kind, BranchStop reason) = 0;
    // The ray's color, before its parent clamps it.
    virtual void endRay(const Vec3& color) = 0;
};

}  // namespace ray
