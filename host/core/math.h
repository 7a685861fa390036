// Small double-precision vector and affine-transform types for the host side.
//
// The scene loader and the reference renderer work in double precision; the packed
// device buffers (see cl/shared_types.h) are filled from these in float.
#pragma once

#include <algorithm>
#include <cmath>

namespace ray {

constexpr double kPi = 3.14159265358979323846;

struct Vec3 {
    double x = 0, y = 0, z = 0;

    constexpr Vec3() = default;
    constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

    constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    // Component-wise product: colors times colors.
    constexpr Vec3 operator*(const Vec3& o) const { return {x * o.x, y * o.y, z * o.z}; }
    Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
};

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
inline Vec3 normalize(const Vec3& v) {
    double len = length(v);
    return len > 0 ? v / len : v;
}
inline Vec3 clamp01(const Vec3& c) {
    return {std::clamp(c.x, 0.0, 1.0), std::clamp(c.y, 0.0, 1.0), std::clamp(c.z, 0.0, 1.0)};
}
inline double maxComponent(const Vec3& v) { return std::max({v.x, v.y, v.z}); }
inline Vec3 componentMin(const Vec3& a, const Vec3& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3 componentMax(const Vec3& a, const Vec3& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline double radians(double degrees) { return degrees * kPi / 180.0; }

// An affine transform: a 3×4 matrix, row-major, translation in the last column; the
// implied fourth row is (0 0 0 1). Stored instead of a full 4×4 because the flattened
// scene holds two of these per primitive instance and scenes reach millions of instances.
struct Affine {
    double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

    static Affine identity() { return {}; }
    static Affine translation(const Vec3& t);
    static Affine scaling(const Vec3& s);
    // Rotation by angleDegrees about axis (right-handed, axis need not be unit length).
    static Affine rotation(const Vec3& axis, double angleDegrees);

    Vec3 transformPoint(const Vec3& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3 transformVector(const Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    // Multiplies v by the transpose of the linear part. Called on a world-to-object
    // transform this maps an object-space normal to world space (the inverse transpose
    // of object-to-world), unnormalized.
    Vec3 transposeTransformVector(const Vec3& v) const {
        return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
                m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
                m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
    }
    double determinant() const;
    // The inverse; a singular transform (a zero scale) yields a matrix of NaNs, which
    // the loader rejects with an error.
    Affine inverse() const;
};

// a * b: applies b first, then a.
Affine operator*(const Affine& a, const Affine& b);

}  // namespace ray
