#include "core/math.h"

#include <limits>

namespace ray {

Affine Affine::translation(const Vec3& t) {
    Affine a;
    a.m[0][3] = t.x;
    a.m[1][3] = t.y;
    a.m[2][3] = t.z;
    return a;
}

Affine Affine::scaling(const Vec3& s) {
    Affine a;
    a.m[0][0] = s.x;
    a.m[1][1] = s.y;
    a.m[2][2] = s.z;
    return a;
}

Affine Affine::rotation(const Vec3& axis, double angleDegrees) {
    // Rodrigues' formula.
    Vec3 k = normalize(axis);
    double c = std::cos(radians(angleDegrees)), s = std::sin(radians(angleDegrees)), t = 1 - c;
    Affine a;
    a.m[0][0] = t * k.x * k.x + c;
    a.m[0][1] = t * k.x * k.y - s * k.z;
    a.m[0][2] = t * k.x * k.z + s * k.y;
    a.m[1][0] = t * k.x * k.y + s * k.z;
    a.m[1][1] = t * k.y * k.y + c;
    a.m[1][2] = t * k.y * k.z - s * k.x;
    a.m[2][0] = t * k.x * k.z - s * k.y;
    a.m[2][1] = t * k.y * k.z + s * k.x;
    a.m[2][2] = t * k.z * k.z + c;
    return a;
}

double Affine::determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Affine Affine::inverse() const {
    Affine r;
    double det = determinant();
    if (det == 0 || !std::isfinite(det)) {
        for (auto& row : r.m)
            for (double& v : row) v = std::numeric_limits<double>::quiet_NaN();
        return r;
    }
    double inv = 1.0 / det;
    r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * inv;
    r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * inv;
    r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * inv;
    r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * inv;
    r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * inv;
    r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * inv;
    r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * inv;
    r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * inv;
    r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * inv;
    // Inverse translation: -R⁻¹ t.
    for (int i = 0; i < 3; ++i)
        r.m[i][3] = -(r.m[i][0] * m[0][3] + r.m[i][1] * m[1][3] + r.m[i][2] * m[2][3]);
    return r;
}

Affine operator*(const Affine& a, const Affine& b) {
    Affine r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            double v = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
            if (j == 3) v += a.m[i][3];
            r.m[i][j] = v;
        }
    }
    return r;
}

}  // namespace ray
