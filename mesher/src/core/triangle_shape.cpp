// triangle_shape.cpp — the measures of one triangle (triangle_shape.hpp).
#include "warpmesh/core/triangle_shape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace warpmesh {

namespace {

constexpr double deg_per_rad = 180.0 / std::numbers::pi;

Vec2 operator-(Vec2 p, Vec2 q) { return {p.x - q.x, p.y - q.y}; }
double dot(Vec2 u, Vec2 v) { return u.x * v.x + u.y * v.y; }
double cross(Vec2 u, Vec2 v) { return u.x * v.y - u.y * v.x; }

// Angle at p between p→q and p→r, in degrees, in [0, 180].
double angle_at(Vec2 p, Vec2 q, Vec2 r) {
    const Vec2 u = q - p, v = r - p;
    return std::atan2(std::abs(cross(u, v)), dot(u, v)) * deg_per_rad;
}

}  // namespace

TriangleShape triangle_shape(Vec2 a, Vec2 b, Vec2 c) {
    // Squared side lengths opposite a, b, c.
    const Vec2 ab = b - a, bc = c - b, ca = a - c;
    const double l[3] = {dot(bc, bc), dot(ca, ca), dot(ab, ab)};
    const Vec2 p[3] = {a, b, c};
    // The vertex opposite the shortest side has the smallest angle, the vertex
    // opposite the longest side the largest (law of sines).
    int imin = 0, imax = 0;
    for (int i = 1; i < 3; ++i) {
        if (l[i] < l[imin]) imin = i;
        if (l[i] > l[imax]) imax = i;
    }
    if (imin == imax) imax = (imin + 1) % 3;  // all sides equal (or all zero)
    auto at = [&](int i) { return angle_at(p[i], p[(i + 1) % 3], p[(i + 2) % 3]); };

    const double x = cross(ab, c - a);
    const double la = std::sqrt(l[0]), lb = std::sqrt(l[1]), lc = std::sqrt(l[2]);
    const double denom = (la + lb + lc) * la * lb * lc;
    const double ratio = denom > 0 ? std::min(1.0, 4 * x * x / denom) : 0.0;
    return {{at(imin), at(imax)}, ratio, x};
}

TriangleAngles triangle_angles(Vec2 a, Vec2 b, Vec2 c) { return triangle_shape(a, b, c).angles; }

double triangle_min_angle(Vec2 a, Vec2 b, Vec2 c) {  // triangle_shape()'s imin, and its angle
    const Vec2 ab = b - a, bc = c - b, ca = a - c;
    const double l[3] = {dot(bc, bc), dot(ca, ca), dot(ab, ab)};
    const Vec2 p[3] = {a, b, c};
    int imin = 0;
    for (int i = 1; i < 3; ++i)
        if (l[i] < l[imin]) imin = i;
    return angle_at(p[imin], p[(imin + 1) % 3], p[(imin + 2) % 3]);
}

double radius_ratio(Vec2 a, Vec2 b, Vec2 c) { return triangle_shape(a, b, c).ratio; }

}  // namespace warpmesh
