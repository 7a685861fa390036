// The host reference renderer: SPEC §3 (camera, sampling) and §4 (lighting) in plain
// double precision. Each function below is one step of the model.
#include "reference/reference_renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "reference/bump_mapping.h"
#include "reference/course_sampling.h"
#include "reference/optics.h"
#include "core/random.h"
#include "reference/reference_bvh.h"
#include "reference/shapes.h"
#include "reference/texture_filtering.h"
#include "reference/texture_sampling.h"
#include "reference/trace_observer.h"

namespace ray {

namespace {

using reference::Aabb;
using reference::SceneHit;
using reference::SceneIntersector;
using reference::SceneSearch;

// Shadow and reflection rays leave from the hit point moved off the surface along the
// normal by this fraction of the scene's size. The hit point is computed in floating
// point and lies a little in front of or behind the true surface (about 1e-15 of the
// scene's size in double precision); a ray leaving from behind would hit the surface it
// leaves (shadow acne, speckled reflections). 1e-9 clears that error by a wide margin
// and is still far smaller than any detail of a scene: the tiniest spheres of
// recursiveSpheres10.xml are a few 1e-4 of the scene (camera included) across.
constexpr double kSurfaceOffset = 1e-9;

// The unlit color of the world: rays that leave the scene add black (SPEC §4).
const Vec3 kBackground{0, 0, 0};

// The course's depth of field (SPEC §3): the lens rays of one sample, a 5 × 5 grid.
constexpr int kLensGridRays = RAY_LENS_GRID_SIDE * RAY_LENS_GRID_SIDE;

struct Ray {
    Vec3 origin;
    Vec3 direction;  // unit length
};

// The pinhole camera of SPEC §3, and the thin lens for depth of field: the course's grid
// of lens points (SPEC §3), or with --dof disk a random point of the lens disk.
class CameraModel {
public:
    CameraModel(const Camera& camera, const RenderSettings& settings)
        : eye_(camera.position), width_(settings.width), height_(settings.height) {
        forward_ = normalize(camera.look);
        right_ = normalize(cross(camera.look, camera.up));  // U = look × up
        up_ = cross(right_, forward_);                       // V = U × look
        halfHeight_ = std::tan(radians(camera.heightAngleDegrees) / 2);
        halfWidth_ = halfHeight_ * double(width_) / double(height_);
        lensRadius_ = settings.depthOfField ? camera.aperture / 2 : 0;
        lensGrid_ = lensRadius_ > 0 && settings.dofMode == DofMode::Course;
        // An unset focal length focuses where the camera looks: at the focus point for
        // a camera given by <focus> (look = focus − pos).
        focalLength_ = camera.focalLength > 0 ? camera.focalLength : length(camera.look);
    }

    // The point of the view plane at depth 1 along the look axis that image position
    // (x, y) = (i + sx, j + sy) sees.
    Vec3 viewPlanePoint(double x, double y) const {
        double u = 2 * x / width_ - 1;
        double v = 1 - 2 * y / height_;
        return u * halfWidth_ * right_ + v * halfHeight_ * up_ + forward_;
    }

    // The pinhole ray through image position (x, y).
    Ray pinholeRay(double x, double y) const { return {eye_, normalize(viewPlanePoint(x, y))}; }

    // --dof disk: the eye moves to a point of the lens disk (diameter aperture, in the
    // plane of U and V) picked by lensX, lensY ∈ [0, 1), and the ray aims at the point the
    // pinhole ray reaches at distance focallength, which stays sharp.
    Ray cameraRay(double x, double y, double lensX, double lensY) const {
        Ray pinhole = pinholeRay(x, y);
        if (lensRadius_ <= 0) return pinhole;
        Vec3 focus = pinhole.origin + focalLength_ * pinhole.direction;
        double r = lensRadius_ * std::sqrt(lensX), phi = 2 * kPi * lensY;  // uniform on the disk
        Vec3 lensPoint = eye_ + r * std::cos(phi) * right_ + r * std::sin(phi) * up_;
        return {lensPoint, normalize(focus - lensPoint)};
    }

    // The course's lens (SPEC §3): lens ray `index` of the grid leaves from
    // pos + (i·a/2)·U + (j·a/2)·V, i = index % side − 2, j = index / side − 2 (a/2 is the
    // lens radius), aimed where the pinhole ray meets the plane at depth focallength along
    // the look axis (not at that distance along the ray).
    Ray gridLensRay(double x, double y, int index) const {
        Vec3 focus = eye_ + focalLength_ * viewPlanePoint(x, y);
        const int half = RAY_LENS_GRID_SIDE / 2;
        double i = index % RAY_LENS_GRID_SIDE - half, j = index / RAY_LENS_GRID_SIDE - half;
        Vec3 lensPoint = eye_ + i * lensRadius_ * right_ + j * lensRadius_ * up_;
        return {lensPoint, normalize(focus - lensPoint)};
    }

    bool hasLens() const { return lensRadius_ > 0; }
    // Whether a sample is the mean of the course's kLensGridRays lens rays (else one ray).
    bool lensGrid() const { return lensGrid_; }

private:
    Vec3 eye_, forward_, right_, up_;
    int width_, height_;
    double halfWidth_ = 0, halfHeight_ = 0;
    double lensRadius_ = 0, focalLength_ = 0;
    bool lensGrid_ = false;
};

// What the lighting model needs to know about a hit, in world space.
struct SurfaceHit {
    Vec3 point;
    Vec3 normal;  // unit length, facing the incoming ray
    bool entering = true;  // the ray meets the outside of the surface (the object normal points outward)
    UV uv;
    const Material* material = nullptr;
    double textureFootprint = 0;  // in texture coordinates; trilinear filtering only (texture_filtering.h)
};

// Where a light's rays come from, seen from a surface point.
struct LightPath {
    Vec3 toLight;     // L: unit vector from the point to the light
    double distance;  // to the light; infinite for a directional light
};

// f_att = min(1, 1/(c1 + c2·d + c3·d²)) (SPEC §4).
double distanceAttenuation(const Vec3& coefficients, double distance) {
    double denominator = coefficients.x + coefficients.y * distance + coefficients.z * distance * distance;
    return denominator > 0 ? std::min(1.0, 1.0 / denominator) : 1.0;
}

// The spot light's cone (SPEC §4): full inside angle − penumbra, nothing outside angle,
// and the smooth step 1 − (3x² − 2x³) across the band between them.
double spotFalloff(const Light& light, const Vec3& toLight) {
    double cosTheta = dot(-toLight, normalize(light.direction));
    double theta = std::acos(std::clamp(cosTheta, -1.0, 1.0));
    double outer = radians(light.angleDegrees);
    double inner = radians(light.angleDegrees - light.penumbraDegrees);
    if (theta <= inner) return 1;
    if (theta >= outer) return 0;
    double x = (theta - inner) / (outer - inner);
    return 1 - (3 * x * x - 2 * x * x * x);
}

// The path to a light at `position` (a point or spot light's own, or one sample of an
// area light's rectangle); a directional light ignores it.
LightPath pathToLight(const Light& light, const Vec3& position, const Vec3& point) {
    if (light.type == LightType::Directional) return {normalize(-light.direction), INFINITY};
    Vec3 offset = position - point;
    double distance = length(offset);
    return {offset / distance, distance};
}

// The light's intensity factor at the point before shadowing: f_att, and the spot cone.
double lightFactor(const Light& light, const LightPath& path) {
    if (light.type == LightType::Directional) return 1;
    double factor = distanceAttenuation(light.attenuation, path.distance);
    if (light.type == LightType::Spot) factor *= spotFalloff(light, path.toLight);
    return factor;
}

Vec3 reflect(const Vec3& direction, const Vec3& normal) { return direction - 2 * dot(direction, normal) * normal; }

bool belowThresholdEverywhere(const Vec3& weight, double threshold) { return maxComponent(weight) < threshold; }

// Which camera sample a ray belongs to: area lights draw their jitter from its random
// numbers (host/core/random.h), as the kernel does. time: its shutter time (motion blur), which
// every ray of its tree, shadow rays included, shares.
struct SampleId {
    uint32_t pixel = 0, sample = 0;
    double time = 0;
};

// Traces rays through one scene with one set of settings. Shared by the render threads:
// everything it holds is read-only; each thread counts its rays in its own RayCounts.
class Tracer {
public:
    // observer: null for image renders; renderReferencePixel's single thread passes one.
    Tracer(const Scene& scene, const RenderSettings& settings, SceneSearch search, TraceObserver* observer = nullptr)
        : scene_(scene), settings_(settings), intersector_(scene, search, settings.courseMeshes), observer_(observer) {
        Aabb bounds = intersector_.sceneBounds();
        bounds.grow(scene.camera.position);
        surfaceOffset_ = kSurfaceOffset * std::max(1e-6, length(bounds.hi - bounds.lo));
        if (settings.textureFilter == TextureFilter::Trilinear) prepareTrilinear();
    }

    Vec3 traceCameraRay(const Ray& ray, const SampleId& id, RayCounts& counts) const {
        ++counts.primary;
        if (observer_) observer_->beginRay(TraceRayKind::Camera, ray.origin, ray.direction, 0, {1, 1, 1}, {1, 1, 1});
        return trace(ray, 0, Vec3{1, 1, 1}, MediumStack{}, id, counts);  // the camera is in air
    }

private:
    // The color seen along the ray. depth: bounces so far; weight: the product of the
    // reflection and transmission factors that will scale this color on its way to the
    // camera; media: what the ray travels through.
    Vec3 trace(const Ray& ray, int depth, const Vec3& weight, const MediumStack& media, const SampleId& id,
               RayCounts& counts) const {
        auto hit = intersector_.closestHit(ray.origin, ray.direction, 0, INFINITY, id.time);
        if (!hit) {
            if (observer_) {
                observer_->miss();
                observer_->endRay(kBackground);
            }
            return kBackground;
        }
        SurfaceHit surface = surfaceAt(*hit, ray, id.time);
        if (observer_) observer_->hit({hit->primitive, hit->local.t, surface.point, surface.normal, surface.entering, surface.uv});
        Vec3 color = shade(surface, ray, depth, weight, media, id, counts);
        if (observer_) observer_->endRay(color);
        return color;
    }

    // The object-space normal, tilted by the material's bump map if it has one.
    Vec3 shadingObjectNormal(const SceneHit& hit, const Ray& ray, double time) const {
        const PrimitiveInstance& instance = surfaceInstance(scene_, hit);
        const TextureMap& map = scene_.materials[instance.material].bumpMap;
        if (!settings_.textures || map.image < 0 || scene_.images[map.image].empty()) return hit.local.normal;
        Vec3 objectPoint =
            instance.worldToObject.transformPoint(ray.origin - time * instance.motion + hit.local.t * ray.direction);
        Vec3 tangent = instance.type == PrimitiveType::Mesh
                           ? hit.local.tangent
                           : objectTangent(instance.type, objectPoint, hit.local.normal);
        HeightSlope slope = heightSlope(scene_.images[map.image], hit.local.uv.u, hit.local.uv.v, map.repeatU, map.repeatV);
        return bumpedNormal(hit.local.normal, tangent, slope, hit.local.bitangentSign);
    }

    SurfaceHit surfaceAt(const SceneHit& hit, const Ray& ray, double time) const {
        const PrimitiveInstance& instance = surfaceInstance(scene_, hit);
        SurfaceHit surface;
        surface.point = ray.origin + hit.local.t * ray.direction;
        // Normals go to world space by the inverse transpose of object-to-world: the
        // transpose of world-to-object.
        // Which side the ray meets is the surface's own: a bump map tilts the shading
        // normal, not the surface, so it must not turn a ray entering glass into one leaving.
        surface.entering = dot(instance.worldToObject.transposeTransformVector(hit.local.normal), ray.direction) < 0;
        surface.normal = normalize(instance.worldToObject.transposeTransformVector(shadingObjectNormal(hit, ray, time)));
        if (!surface.entering) surface.normal = -surface.normal;
        surface.uv = hit.local.uv;
        surface.material = &scene_.materials[instance.material];
        if (settings_.textureFilter == TextureFilter::Trilinear) {
            double density = instance.type == PrimitiveType::Mesh ? meshUvDensities_[size_t(instance.mesh)]
                                                                  : primitiveUvDensity(instance.type);
            surface.textureFootprint = textureFootprint(spreadAngle_, hit.local.t, ray.direction, surface.normal,
                                                        instance.worldToObject, density);
        }
        return surface;
    }

    // I = ka·Oa + Oe + Σ lights + ks·Or·I_r + kt·Ot·I_t (SPEC §4).
    Vec3 shade(const SurfaceHit& surface, const Ray& ray, int depth, const Vec3& weight, const MediumStack& media,
               const SampleId& id, RayCounts& counts) const {
        if (leavesTransparentObject(surface)) return transmittedFromInside(surface, ray, depth, weight, media, id, counts);
        const Material& material = *surface.material;
        const GlobalCoefficients& k = scene_.globals;
        Vec3 color = k.ka * material.ambient + material.emissive;

        Vec3 texel;
        Vec3 diffuse = diffuseColor(surface, &texel);
        if (observer_)
            observer_->surfaceTerms(k.ka * material.ambient, material.emissive, diffuse, textured(material), texel);
        Vec3 toEye = -ray.direction;
        for (size_t i = 0; i < scene_.lights.size(); ++i)
            color += lightContribution(scene_.lights[i], int(i), surface, diffuse, toEye, id, counts);

        // --fresnel: ks·Or·R·I_r + kt·Ot·(1 − R)·I_t on a transparent surface.
        std::optional<double> r = surfaceReflectance(surface, ray, media);
        color += reflection(surface, ray, depth, weight, media, id, counts, r ? *r : 1.0);
        color += refraction(surface, ray, depth, weight, media, id, counts, r ? 1 - *r : 1.0);
        return color;
    }

    // A light's term; an area light's is the sum over its side × side jittered samples
    // (optics.h), each a point light with 1/side² of the intensity and its own shadow ray.
    Vec3 lightContribution(const Light& light, int index, const SurfaceHit& surface, const Vec3& diffuse,
                           const Vec3& toEye, const SampleId& id, RayCounts& counts) const {
        if (light.type != LightType::Area)
            return directLight(light, index, -1, light.position, light.color, surface, diffuse, toEye, id.time, counts);
        const int side = areaLightGridSide(settings_);
        const Vec3 intensity = light.color / double(side * side);
        Vec3 sum;
        for (int cell = 0; cell < side * side; ++cell) {
            Vec3 position = areaLightPoint(light, index, cell, side, id.pixel, id.sample, settings_.seed);
            sum += directLight(light, index, cell, position, intensity, surface, diffuse, toEye, id.time, counts);
        }
        return sum;
    }

    bool textured(const Material& material) const {
        const TextureMap& map = material.texture;
        return settings_.textures && map.image >= 0 && !scene_.images[map.image].empty();
    }

    // D = blend·T + (1 − blend)·kd·Od, T not scaled by kd; without a texture, kd·Od.
    // texelOut, when given, receives T.
    Vec3 diffuseColor(const SurfaceHit& surface, Vec3* texelOut = nullptr) const {
        const Material& material = *surface.material;
        Vec3 plain = scene_.globals.kd * material.diffuse;
        const TextureMap& map = material.texture;
        if (!textured(material)) return plain;
        Vec3 texel = settings_.textureFilter == TextureFilter::Trilinear
                         ? sampleTrilinear(mipmaps_[size_t(map.image)], surface.uv.u, surface.uv.v, map.repeatU,
                                           map.repeatV, surface.textureFootprint)
                         : sampleTexture(scene_.images[map.image], surface.uv.u, surface.uv.v, map.repeatU,
                                         map.repeatV, settings_.textureFilter);
        if (texelOut) *texelOut = texel;
        return material.blend * texel + (1 - material.blend) * plain;
    }

    // f_att · S · I_L · [D·max(N·L, 0) + ks·Os·max(R·V, 0)^n] for a light at `position`
    // with intensity I_L; nothing where N·L ≤ 0. index, cell: which light (and area-light
    // sample) this is, for the observer.
    Vec3 directLight(const Light& light, int index, int cell, const Vec3& position, const Vec3& intensity,
                     const SurfaceHit& surface, const Vec3& diffuse, const Vec3& toEye, double time,
                     RayCounts& counts) const {
        TraceLightTerm term;
        term.light = index;
        term.areaCell = cell;
        LightPath path = pathToLight(light, position, surface.point);
        term.toLight = path.toLight;
        term.distance = path.distance;
        double lambert = term.nDotL = dot(surface.normal, path.toLight);
        if (lambert <= 0) return unlit(term, "back-facing");
        double factor = term.attenuation = lightFactor(light, path);
        if (factor <= 0) return unlit(term, "outside the light");
        if (settings_.shadows && blocked(surface, path, time, counts, term)) return unlit(term, "shadowed");

        const Material& material = *surface.material;
        Vec3 mirrored = reflect(-path.toLight, surface.normal);  // R: L reflected about N
        double highlight = std::pow(term.rDotV = std::max(dot(mirrored, toEye), 0.0), material.shininess);
        Vec3 response = (term.diffuse = diffuse * lambert) + (term.specular = scene_.globals.ks * material.specular * highlight);
        Vec3 contribution = factor * intensity * response;
        if (observer_) {
            term.contribution = contribution;
            observer_->lightTerm(term);
        }
        return contribution;
    }

    // A light term that adds nothing, reported with why.
    Vec3 unlit(TraceLightTerm& term, const char* reason) const {
        if (observer_) {
            term.unlitReason = reason;
            observer_->lightTerm(term);
        }
        return {};
    }

    // S = 0 when any surface lies between the point and the light. With an observer, the
    // nearest such surface is named too (a second search, for the report only).
    bool blocked(const SurfaceHit& surface, const LightPath& path, double time, RayCounts& counts,
                 TraceLightTerm& term) const {
        ++counts.shadow;
        Vec3 origin = surface.point + surfaceOffset_ * surface.normal;  // N·L > 0: the lit side
        bool any = intersector_.anyHit(origin, path.toLight, 0, path.distance, time);
        term.shadowed = any;
        if (any && observer_) {
            auto occluder = intersector_.closestHit(origin, path.toLight, 0, path.distance, time);
            if (occluder) term.occluder = occluder->primitive;
        }
        return any;
    }

    // The factor k·color·share of a reflected (ks·Or) or refracted (kt·Ot) branch, or
    // nullopt where its switch, the depth limit or the weight threshold stops it (SPEC §4;
    // the observer hears which). share: the branch's Fresnel share (R or 1 − R) with
    // --fresnel, else 1; a share of 0 (total internal reflection, no interface) is no branch.
    std::optional<Vec3> branchFactor(TraceRayKind kind, bool enabled, double k, const Vec3& color, int depth,
                                     const Vec3& weight, double share = 1) const {
        auto stop = [&](BranchStop reason) -> std::optional<Vec3> {
            if (observer_) observer_->branchStopped(kind, reason);
            return std::nullopt;
        };
        if (!enabled) return stop(BranchStop::Disabled);
        if (color == Vec3{}) return stop(BranchStop::NoCoefficient);
        if (share == 0) return stop(BranchStop::NoFresnelShare);
        if (depth >= settings_.maxDepth) return stop(BranchStop::DepthLimit);
        Vec3 factor = k * color * share;
        if (belowThresholdEverywhere(weight * factor, settings_.weightThreshold)) return stop(BranchStop::WeightThreshold);
        return factor;
    }

    // --fresnel (SPEC §4): R, the exact Fresnel reflectance of a transparent object's
    // surface (Ot ≠ 0) for the ray meeting it, from the medium the ray is in into the one
    // beyond (optics.h). nullopt where the weighting does not apply: without --fresnel, on
    // opaque surfaces, and with refraction off (transparent objects are opaque then).
    std::optional<double> surfaceReflectance(const SurfaceHit& surface, const Ray& ray, const MediumStack& media) const {
        const Material& material = *surface.material;
        if (!settings_.fresnel || !settings_.refraction || material.transparent == Vec3{}) return std::nullopt;
        double n1 = media.before(surface.entering, material.ior);
        double n2 = media.beyond(surface.entering, material.ior).current();
        return fresnelReflectance(-dot(ray.direction, surface.normal), n1, n2);
    }

    // ks·Or·I_r with I_r clamped to [0, 1], while depth and weight allow (SPEC §4); times
    // share = R with --fresnel on a transparent surface.
    Vec3 reflection(const SurfaceHit& surface, const Ray& ray, int depth, const Vec3& weight, const MediumStack& media,
                    const SampleId& id, RayCounts& counts, double share) const {
        auto factor = branchFactor(TraceRayKind::Reflected, settings_.reflections, scene_.globals.ks,
                                   surface.material->reflective, depth, weight, share);
        if (!factor) return {};
        return *factor * mirrored(surface, ray, depth, weight * *factor, *factor, TraceRayKind::Reflected, media, id, counts);
    }

    // clamp(I_r): the mirrored ray, which stays in the medium it came from. branchWeight,
    // factor: as for transmitted().
    Vec3 mirrored(const SurfaceHit& surface, const Ray& ray, int depth, const Vec3& branchWeight, const Vec3& factor,
                  TraceRayKind kind, const MediumStack& media, const SampleId& id, RayCounts& counts) const {
        ++counts.secondary;
        Ray reflected{surface.point + surfaceOffset_ * surface.normal, normalize(reflect(ray.direction, surface.normal))};
        if (observer_) observer_->beginRay(kind, reflected.origin, reflected.direction, depth + 1, branchWeight, factor);
        return clamp01(trace(reflected, depth + 1, branchWeight, media, id, counts));
    }

    // kt·Ot·I_t with I_t clamped to [0, 1] (SPEC §4), for a surface met from outside; times
    // share = 1 − R with --fresnel.
    Vec3 refraction(const SurfaceHit& surface, const Ray& ray, int depth, const Vec3& weight, const MediumStack& media,
                    const SampleId& id, RayCounts& counts, double share) const {
        const Material& material = *surface.material;
        auto factor = branchFactor(TraceRayKind::Refracted, settings_.refraction, scene_.globals.kt,
                                   material.transparent, depth, weight, share);
        if (!factor) return {};

        return *factor * transmitted(surface, ray, depth, weight * *factor, *factor, media, id, counts);
    }

    // A transparent object's surface met from inside (SPEC §4) adds nothing of its own:
    // I = clamp(I_t) with weight 1, so that kt·Ot applies once per object, on entry.
    bool leavesTransparentObject(const SurfaceHit& surface) const {
        return settings_.refraction && !surface.entering && surface.material->transparent != Vec3{};
    }

    // With --fresnel the light splits there as well and the reflected part is kept inside
    // the object: I = R·clamp(I_r) + (1 − R)·clamp(I_t), I_r along the mirrored ray, which
    // stays inside. Under total internal reflection R = 1: the mirrored ray alone, as
    // without --fresnel. Both branches belong to refraction (--no-reflections keeps them);
    // each counts a bounce and --threshold cuts it by its own weight (R or 1 − R times the
    // path weight).
    Vec3 transmittedFromInside(const SurfaceHit& surface, const Ray& ray, int depth, const Vec3& weight,
                               const MediumStack& media, const SampleId& id, RayCounts& counts) const {
        const Vec3 one{1, 1, 1};
        std::optional<double> r = surfaceReflectance(surface, ray, media);
        if (!r) {
            // Weight 1: the shared gate then stops only at the depth limit, and tells the observer.
            auto factor = branchFactor(TraceRayKind::Refracted, settings_.refraction, 1.0, one, depth, weight);
            if (!factor) return {};
            return transmitted(surface, ray, depth, weight, *factor, media, id, counts);
        }
        Vec3 color;
        TraceRayKind inner = *r == 1 ? TraceRayKind::TotalInternalReflection : TraceRayKind::Reflected;
        if (auto factor = branchFactor(inner, true, 1.0, one, depth, weight, *r))
            color += *factor * mirrored(surface, ray, depth, weight * *factor, *factor, inner, media, id, counts);
        if (auto factor = branchFactor(TraceRayKind::Refracted, true, 1.0, one, depth, weight, 1 - *r))
            color += *factor * transmitted(surface, ray, depth, weight * *factor, *factor, media, id, counts);
        return color;
    }

    // clamp(I_t): the ray refracted by Snell's law into the medium beyond the surface, or
    // under total internal reflection the mirrored ray, which stays in the medium it came
    // from. branchWeight: the path weight of the branch; factor: what the caller multiplies
    // I_t by (kt·Ot on entry, 1 from inside), reported to the observer.
    Vec3 transmitted(const SurfaceHit& surface, const Ray& ray, int depth, const Vec3& branchWeight,
                     const Vec3& factor, const MediumStack& media, const SampleId& id, RayCounts& counts) const {
        const Material& material = *surface.material;
        ++counts.secondary;
        double n1 = media.before(surface.entering, material.ior);
        MediumStack beyond = media.beyond(surface.entering, material.ior);
        Vec3 direction;
        Ray child;
        MediumStack childMedia = media;
        TraceRayKind kind = TraceRayKind::Refracted;
        if (refractDirection(ray.direction, surface.normal, n1, beyond.current(), direction)) {
            child = {surface.point - surfaceOffset_ * surface.normal, direction};  // start on the far side
            childMedia = beyond;
        } else {
            child = {surface.point + surfaceOffset_ * surface.normal, normalize(reflect(ray.direction, surface.normal))};
            kind = TraceRayKind::TotalInternalReflection;
        }
        if (observer_) observer_->beginRay(kind, child.origin, child.direction, depth + 1, branchWeight, factor);
        return clamp01(trace(child, depth + 1, branchWeight, childMedia, id, counts));
    }

    // Mipmaps of every image, the meshes' UV densities and the pixel spread angle.
    void prepareTrilinear() {
        for (const Image& image : scene_.images) mipmaps_.push_back(buildMipPyramid(image));
        for (const TriangleMesh& mesh : scene_.meshes) meshUvDensities_.push_back(meshUvDensity(mesh));
        spreadAngle_ = pixelSpreadAngle(scene_.camera.heightAngleDegrees, settings_.height);
    }

    const Scene& scene_;
    const RenderSettings& settings_;
    SceneIntersector intersector_;
    TraceObserver* observer_ = nullptr;
    double surfaceOffset_ = 0;
    std::vector<MipPyramid> mipmaps_;      // trilinear filtering only
    std::vector<double> meshUvDensities_;  // trilinear filtering only
    double spreadAngle_ = 0;
};

// Renders rows handed out one at a time to `threads` threads.
class RowRenderer {
public:
    RowRenderer(const Scene& scene, const RenderSettings& settings, const ReferenceRenderOptions& options,
                TraceObserver* observer = nullptr)
        : settings_(settings),
          options_(options),
          camera_(scene.camera, settings),
          tracer_(scene, settings, options.bruteForce ? SceneSearch::BruteForce : SceneSearch::Bvh, observer),
          observer_(observer),
          image_(observer ? 0 : settings.width, observer ? 0 : settings.height) {}

    // The color of pixel (column, row) as the image holds it (before clamping).
    Vec3 pixelColor(int column, int row, RayCounts& counts) const {
        uint32_t pixel = uint32_t(row) * uint32_t(settings_.width) + uint32_t(column);
        // Samples are numbered in the order the sampling pattern asks for them, which
        // is deterministic; the shutter time of sample k comes from dimension 4 of
        // sampleRandom, with --dof disk its lens position from dimensions 2, 3 (0, 1 are
        // the stratified pattern's jitter). With the course's lens grid a sample is the
        // mean of its lens rays' clamped colors (SPEC §3), which share the sample's number.
        uint32_t sampleIndex = 0;
        auto sample = [&](double sx, double sy) {
            uint32_t k = sampleIndex++;
            double lensX = 0, lensY = 0;
            if (camera_.hasLens() && !camera_.lensGrid()) {
                lensX = sampleRandom(pixel, k, 2, settings_.seed);
                lensY = sampleRandom(pixel, k, 3, settings_.seed);
            }
            double time = settings_.shutter > 0 ? settings_.shutter * sampleRandom(pixel, k, 4, settings_.seed) : 0;
            if (observer_) observer_->beginSample(int(k), sx, sy, time);
            const SampleId id{pixel, k, time};
            Vec3 color;
            if (camera_.lensGrid()) {
                Vec3 sum{0, 0, 0};
                for (int lens = 0; lens < kLensGridRays; ++lens)
                    sum = sum + clamp01(tracer_.traceCameraRay(camera_.gridLensRay(column + sx, row + sy, lens), id, counts));
                color = sum / double(kLensGridRays);
            } else {
                color = tracer_.traceCameraRay(camera_.cameraRay(column + sx, row + sy, lensX, lensY), id, counts);
            }
            if (observer_) observer_->endSample(color);
            return color;
        };
        return samplePixel(settings_, pixel, sample);
    }

    Image run(RayCounts* counts) {
        int threads = options_.threads > 0 ? options_.threads : int(std::thread::hardware_concurrency());
        threads = std::clamp(threads, 1, settings_.height);
        std::vector<RayCounts> perThread(threads);
        std::vector<std::thread> workers;
        for (int t = 1; t < threads; ++t) workers.emplace_back([this, &perThread, t] { work(perThread[t]); });
        work(perThread[0]);
        for (std::thread& worker : workers) worker.join();

        if (counts) {
            *counts = {};
            for (const RayCounts& c : perThread) {
                counts->primary += c.primary;
                counts->shadow += c.shadow;
                counts->secondary += c.secondary;
            }
        }
        return std::move(image_);
    }

private:
    void work(RayCounts& counts) {
        for (int row = nextRow_++; row < settings_.height; row = nextRow_++) {
            if (options_.cancel && options_.cancel->load()) return;
            renderRow(row, counts);
            if (options_.rowDone && !(options_.cancel && options_.cancel->load()))
                options_.rowDone(row, &image_.rgb[size_t(row) * size_t(settings_.width) * 3]);
            int done = ++rowsDone_;
            if (options_.progress) options_.progress(double(done) / settings_.height);
        }
    }

    void renderRow(int row, RayCounts& counts) {
        for (int column = 0; column < settings_.width; ++column) {
            // Checked per pixel too: one row of a wide image at many samples can take seconds.
            if (options_.cancel && options_.cancel->load()) return;
            image_.set(column, row, pixelColor(column, row, counts));
        }
    }

    const RenderSettings& settings_;
    const ReferenceRenderOptions& options_;
    CameraModel camera_;
    Tracer tracer_;
    TraceObserver* observer_ = nullptr;
    Image image_;
    std::atomic<int> nextRow_{0};
    std::atomic<int> rowsDone_{0};
};

}  // namespace

Image renderReference(const Scene& scene, const RenderSettings& settings, const ReferenceRenderOptions& options,
                      RayCounts* counts) {
    if (counts) *counts = {};
    if (settings.width <= 0 || settings.height <= 0) return Image(std::max(0, settings.width), std::max(0, settings.height));
    RowRenderer renderer(scene, settings, options);
    return renderer.run(counts);
}

Vec3 renderReferencePixel(const Scene& scene, const RenderSettings& settings, int x, int y, TraceObserver* observer,
                          const ReferenceRenderOptions& options, RayCounts* counts) {
    if (x < 0 || y < 0 || x >= settings.width || y >= settings.height)
        throw std::out_of_range("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                                std::to_string(settings.width) + "x" + std::to_string(settings.height) + " image");
    RayCounts local;
    RowRenderer renderer(scene, settings, options, observer);
    Vec3 color = renderer.pixelColor(x, y, local);
    if (counts) *counts = local;
    return color;
}

const char* traceRayKindName(TraceRayKind kind) {
    switch (kind) {
        case TraceRayKind::Camera: return "camera";
        case TraceRayKind::Reflected: return "reflected";
        case TraceRayKind::Refracted: return "refracted";
        case TraceRayKind::TotalInternalReflection: return "total internal reflection";
    }
    return "?";
}

const char* branchStopName(BranchStop stop) {
    switch (stop) {
        case BranchStop::Disabled: return "switched off";
        case BranchStop::NoCoefficient: return "material has no such color";
        case BranchStop::NoFresnelShare: return "Fresnel share is 0";
        case BranchStop::DepthLimit: return "depth limit";
        case BranchStop::WeightThreshold: return "weight threshold";
    }
    return "?";
}

std::optional<PickedSurface> pickPixel(const Scene& scene, const reference::SceneIntersector& intersector,
                                       const Camera& camera, const RenderSettings& settings, int x, int y) {
    if (x < 0 || y < 0 || x >= settings.width || y >= settings.height)
        throw std::out_of_range("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                                std::to_string(settings.width) + "x" + std::to_string(settings.height) + " image");
    const CameraModel model(camera, settings);
    const Ray ray = model.pinholeRay(x + 0.5, y + 0.5);
    const std::optional<SceneHit> hit = intersector.closestHit(ray.origin, ray.direction, 0, INFINITY, 0);
    if (!hit) return std::nullopt;
    const PrimitiveInstance& instance = surfaceInstance(scene, *hit);
    PickedSurface picked;
    picked.primitive = hit->primitive;
    picked.csgOperand = hit->csgOperand;
    picked.point = ray.origin + hit->local.t * ray.direction;
    picked.normal = normalize(instance.worldToObject.transposeTransformVector(hit->local.normal));
    picked.distance = hit->local.t;
    return picked;
}

}  // namespace ray
