#include "reference/shapes.h"

#include <cmath>
#include <utility>

#include "reference/polynomial.h"

namespace ray {

namespace {

constexpr double kRadius = 0.5;     // sphere, cylinder and cone base
constexpr double kHalfSize = 0.5;   // cube half-extent, cylinder and cone half-height

double fract(double x) { return x - std::floor(x); }

// The part of a quadric-and-caps shape that a root belongs to: it decides the normal and
// the texture mapping, and deciding it from the root (not from the hit point) keeps hits
// on the rims from being mistaken for the neighbouring part.
enum class Surface { Side, TopCap, BottomCap };

// Keeps the smallest root inside (tMin, tMax) among those offered.
class NearestRoot {
public:
    NearestRoot(double tMin, double tMax) : tMin_(tMin), tMax_(tMax) {}

    void offer(double t, Surface surface) {
        if (t > tMin_ && t < tMax_ && (!found_ || t < t_)) {
            found_ = true;
            t_ = t;
            surface_ = surface;
        }
    }
    bool found() const { return found_; }
    double t() const { return t_; }
    Surface surface() const { return surface_; }

private:
    double tMin_, tMax_;
    bool found_ = false;
    double t_ = 0;
    Surface surface_ = Surface::Side;
};

// Roots of a·t² + 2·halfB·t + c = 0 (none, one or two; a degenerate a = 0 is linear).
struct Roots {
    int count = 0;
    double t[2] = {0, 0};
};

Roots solveQuadratic(double a, double halfB, double discriminant) {
    Roots r;
    if (discriminant < 0) return r;
    double root = std::sqrt(discriminant);
    r.count = 2;
    r.t[0] = (-halfB - root) / a;
    r.t[1] = (-halfB + root) / a;
    return r;
}

// The caps of the cylinder and cone: discs of radius 0.5 in the planes y = ±0.5.
void offerCap(const Vec3& origin, const Vec3& direction, double capY, Surface surface, NearestRoot& nearest) {
    if (direction.y == 0) return;
    double t = (capY - origin.y) / direction.y;
    double x = origin.x + t * direction.x, z = origin.z + t * direction.z;
    if (x * x + z * z <= kRadius * kRadius) nearest.offer(t, surface);
}

bool withinHeight(double y) { return y >= -kHalfSize && y <= kHalfSize; }

// Side u as the sphere's, v = y + 0.5; caps as the cube's ±y faces (SPEC §5).
ShapeHit capOrSideHit(const Vec3& point, double t, Surface surface, const Vec3& sideNormal) {
    ShapeHit hit;
    hit.t = t;
    switch (surface) {
        case Surface::Side:
            hit.normal = sideNormal;
            hit.uv = {sphericalU(point), std::clamp(point.y + 0.5, 0.0, 1.0)};
            break;
        case Surface::TopCap:
            hit.normal = {0, 1, 0};
            hit.uv = cubeFaceUV(point, hit.normal);
            break;
        case Surface::BottomCap:
            hit.normal = {0, -1, 0};
            hit.uv = cubeFaceUV(point, hit.normal);
            break;
    }
    return hit;
}

// Direction away from the y axis in the xz plane; zero on the axis itself.
Vec3 radialDirection(const Vec3& point) { return normalize(Vec3{point.x, 0, point.z}); }

}  // namespace

double sphericalU(const Vec3& point) { return fract(std::atan2(-point.z, point.x) / (2 * kPi)); }

UV cubeFaceUV(const Vec3& point, const Vec3& faceNormal) {
    // Points on the face lie in [-0.5, 0.5]; clamping keeps rounding out of [0, 1].
    double x = std::clamp(point.x, -0.5, 0.5), y = std::clamp(point.y, -0.5, 0.5), z = std::clamp(point.z, -0.5, 0.5);
    if (faceNormal.z > 0.5) return {x + 0.5, y + 0.5};
    if (faceNormal.z < -0.5) return {0.5 - x, y + 0.5};
    if (faceNormal.x > 0.5) return {0.5 - z, y + 0.5};
    if (faceNormal.x < -0.5) return {z + 0.5, y + 0.5};
    if (faceNormal.y > 0.5) return {x + 0.5, 0.5 - z};
    return {x + 0.5, z + 0.5};  // -y
}

std::optional<ShapeHit> intersectCube(const Vec3& origin, const Vec3& direction, double tMin, double tMax) {
    // Slabs: the ray is inside the cube between the largest entering and the smallest
    // leaving plane distance. Each end remembers its face for the normal.
    double tEnter = -INFINITY, tLeave = INFINITY;
    Vec3 enterNormal, leaveNormal;
    for (int axis = 0; axis < 3; ++axis) {
        double o = origin[axis], d = direction[axis];
        if (d == 0) {
            // Parallel to this slab: inside it everywhere or nowhere.
            if (o < -kHalfSize || o > kHalfSize) return std::nullopt;
            continue;
        }
        double tLow = (-kHalfSize - o) / d, tHigh = (kHalfSize - o) / d;
        Vec3 lowFace, highFace;
        lowFace[axis] = -1;
        highFace[axis] = 1;
        if (tLow > tHigh) {
            std::swap(tLow, tHigh);
            std::swap(lowFace, highFace);
        }
        if (tLow > tEnter) {
            tEnter = tLow;
            enterNormal = lowFace;
        }
        if (tHigh < tLeave) {
            tLeave = tHigh;
            leaveNormal = highFace;
        }
    }
    if (tEnter > tLeave) return std::nullopt;

    // From outside the nearest hit is where the ray enters; from inside, where it leaves.
    ShapeHit hit;
    if (tEnter > tMin && tEnter < tMax) {
        hit.t = tEnter;
        hit.normal = enterNormal;
    } else if (tLeave > tMin && tLeave < tMax) {
        hit.t = tLeave;
        hit.normal = leaveNormal;
    } else {
        return std::nullopt;
    }
    hit.uv = cubeFaceUV(origin + hit.t * direction, hit.normal);
    return hit;
}

std::optional<ShapeHit> intersectSphere(const Vec3& origin, const Vec3& direction, double tMin, double tMax) {
    // |origin + t·direction|² = r². The discriminant is computed from the ray's closest
    // approach to the centre, a·(r² − |f|²), instead of halfB² − a·c: the textbook form
    // cancels catastrophically when the sphere is small against its distance (the tiny
    // spheres of recursiveSpheres*.xml), this one does not.
    double a = dot(direction, direction);
    double halfB = dot(origin, direction);
    Vec3 closestApproach = origin - (halfB / a) * direction;
    double discriminant = a * (kRadius * kRadius - dot(closestApproach, closestApproach));
    Roots roots = solveQuadratic(a, halfB, discriminant);

    NearestRoot nearest(tMin, tMax);
    for (int i = 0; i < roots.count; ++i) nearest.offer(roots.t[i], Surface::Side);
    if (!nearest.found()) return std::nullopt;

    Vec3 p = origin + nearest.t() * direction;
    ShapeHit hit;
    hit.t = nearest.t();
    hit.normal = normalize(p);
    hit.uv = {sphericalU(p), 0.5 + std::asin(std::clamp(p.y / kRadius, -1.0, 1.0)) / kPi};
    return hit;
}

std::optional<ShapeHit> intersectCylinder(const Vec3& origin, const Vec3& direction, double tMin, double tMax) {
    NearestRoot nearest(tMin, tMax);

    // Side: x² + z² = r² (a 2D circle test, in the same closest-approach form as the
    // sphere's), for y within the height. A ray parallel to the axis (a = 0) misses it.
    double a = direction.x * direction.x + direction.z * direction.z;
    if (a > 0) {
        double halfB = origin.x * direction.x + origin.z * direction.z;
        double fx = origin.x - (halfB / a) * direction.x, fz = origin.z - (halfB / a) * direction.z;
        double discriminant = a * (kRadius * kRadius - (fx * fx + fz * fz));
        Roots roots = solveQuadratic(a, halfB, discriminant);
        for (int i = 0; i < roots.count; ++i)
            if (withinHeight(origin.y + roots.t[i] * direction.y)) nearest.offer(roots.t[i], Surface::Side);
    }
    offerCap(origin, direction, kHalfSize, Surface::TopCap, nearest);
    offerCap(origin, direction, -kHalfSize, Surface::BottomCap, nearest);
    if (!nearest.found()) return std::nullopt;

    Vec3 p = origin + nearest.t() * direction;
    return capOrSideHit(p, nearest.t(), nearest.surface(), radialDirection(p));
}

std::optional<ShapeHit> intersectCone(const Vec3& origin, const Vec3& direction, double tMin, double tMax) {
    NearestRoot nearest(tMin, tMax);

    // Side: x² + z² = (r·(0.5 − y))², the radius shrinking linearly from 0.5 at the base
    // (y = −0.5) to 0 at the apex (y = 0.5). With k = 0.5 − origin.y, 0.5 − y = k − t·dy.
    // Only roots within the height count: the other half of the double cone lies above.
    double k = kHalfSize - origin.y;
    double a = direction.x * direction.x + direction.z * direction.z - 0.25 * direction.y * direction.y;
    double halfB = origin.x * direction.x + origin.z * direction.z + 0.25 * k * direction.y;
    double c = origin.x * origin.x + origin.z * origin.z - 0.25 * k * k;
    Roots roots;
    if (a != 0) {
        roots = solveQuadratic(a, halfB, halfB * halfB - a * c);
    } else if (halfB != 0) {
        // A ray parallel to a generating line: the equation is linear, one root.
        roots.count = 1;
        roots.t[0] = -c / (2 * halfB);
    }
    for (int i = 0; i < roots.count; ++i)
        if (withinHeight(origin.y + roots.t[i] * direction.y)) nearest.offer(roots.t[i], Surface::Side);
    offerCap(origin, direction, -kHalfSize, Surface::BottomCap, nearest);
    if (!nearest.found()) return std::nullopt;

    // The side's outward normal is ∝ (2·radial, 1): the gradient of the implicit form,
    // its slope set by the radius falling 0.5 over a height of 1. At the apex itself the
    // radial direction vanishes and the normal is taken straight up.
    Vec3 p = origin + nearest.t() * direction;
    Vec3 radial = radialDirection(p);
    Vec3 sideNormal = radial == Vec3{} ? Vec3{0, 1, 0} : normalize(2 * radial + Vec3{0, 1, 0});
    return capOrSideHit(p, nearest.t(), nearest.surface(), sideNormal);
}

std::optional<ShapeHit> intersectTorus(const Vec3& origin, const Vec3& direction, double tMin, double tMax) {
    constexpr double R = kTorusMajorRadius, r = kTorusMinorRadius;
    // Work with a unit direction (s = t·|direction|) and start the ray where it enters the
    // torus's bounding box: the quartic's coefficients then stay of the order of the torus
    // itself, however far away the ray starts (the direct form loses every digit to the
    // origin's distance, squared twice).
    double scale = length(direction);
    if (scale == 0) return std::nullopt;
    Vec3 d = direction / scale;
    double sLo = tMin * scale, sHi = tMax * scale;
    const Vec3 half{R + r, r, R + r};
    for (int axis = 0; axis < 3; ++axis) {
        double padded = half[axis] * (1 + 1e-9);
        if (d[axis] == 0) {
            if (std::abs(origin[axis]) > padded) return std::nullopt;
            continue;
        }
        double s0 = (-padded - origin[axis]) / d[axis], s1 = (padded - origin[axis]) / d[axis];
        if (s0 > s1) std::swap(s0, s1);
        sLo = std::max(sLo, s0);
        sHi = std::min(sHi, s1);
        if (sLo > sHi) return std::nullopt;
    }
    Vec3 o = origin + sLo * d;

    // (|p|² + R² − r²)² = 4R²(x² + z²) along p = o + s·d, as a quartic in s (monic).
    double k = dot(o, o) + R * R - r * r, m = dot(o, d);
    double radialD = d.x * d.x + d.z * d.z, radialOD = o.x * d.x + o.z * d.z, radialO = o.x * o.x + o.z * o.z;
    const double c[5] = {k * k - 4 * R * R * radialO, 4 * m * k - 8 * R * R * radialOD,
                         4 * m * m + 2 * k - 4 * R * R * radialD, 4 * m, 1};
    double roots[4];
    int count = polynomialRootsInInterval(c, 4, 0, sHi - sLo, roots);
    const double* root = std::find_if(roots, roots + count, [&](double s) { return sLo + s > tMin * scale; });
    if (root == roots + count) return std::nullopt;

    Vec3 p = o + *root * d;
    double radial = std::sqrt(p.x * p.x + p.z * p.z);
    Vec3 ringPoint = radial > 0 ? Vec3{p.x, 0, p.z} * (R / radial) : Vec3{R, 0, 0};
    ShapeHit hit;
    hit.t = (sLo + *root) / scale;
    hit.normal = normalize(p - ringPoint);
    hit.uv = {sphericalU(p), fract(std::atan2(p.y, radial - R) / (2 * kPi))};
    return hit;
}

std::optional<ShapeHit> intersectUnitPrimitive(PrimitiveType type, const Vec3& origin, const Vec3& direction,
                                               double tMin, double tMax) {
    switch (type) {
        case PrimitiveType::Cube: return intersectCube(origin, direction, tMin, tMax);
        case PrimitiveType::Sphere: return intersectSphere(origin, direction, tMin, tMax);
        case PrimitiveType::Cylinder: return intersectCylinder(origin, direction, tMin, tMax);
        case PrimitiveType::Cone: return intersectCone(origin, direction, tMin, tMax);
        case PrimitiveType::Torus: return intersectTorus(origin, direction, tMin, tMax);
        case PrimitiveType::Mesh:
        case PrimitiveType::Csg: return std::nullopt;  // intersected by their own code (reference_bvh)
    }
    return std::nullopt;
}

}  // namespace ray
