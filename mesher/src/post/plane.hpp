// plane.hpp (internal) — the few vector operations on Vec2, the key of an
// undirected edge, and the angle quality g of the search, that the
// optimisation pass and its local refinement share.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include "warpmesh/core/mesh.hpp"

namespace warpmesh::plane {

inline Vec2 operator-(Vec2 p, Vec2 q) { return {p.x - q.x, p.y - q.y}; }
inline Vec2 operator+(Vec2 p, Vec2 q) { return {p.x + q.x, p.y + q.y}; }
inline Vec2 operator*(double a, Vec2 p) { return {a * p.x, a * p.y}; }
inline double dot(Vec2 u, Vec2 v) { return u.x * v.x + u.y * v.y; }
inline double cross(Vec2 u, Vec2 v) { return u.x * v.y - u.y * v.x; }
inline double norm2(Vec2 u) { return dot(u, u); }
inline Vec2 perp(Vec2 u) { return {-u.y, u.x}; }

// > 0 iff d lies strictly inside the circumcircle of the counter-clockwise
// triangle a, b, c (the in-circle determinant, d as origin).
inline double incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const Vec2 ad = a - d, bd = b - d, cd = c - d;
    return norm2(ad) * cross(bd, cd) + norm2(bd) * cross(cd, ad) + norm2(cd) * cross(ad, bd);
}

// The edge {a, b} in either orientation.
inline std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

constexpr double deg_per_rad = 180.0 / std::numbers::pi;
// g(θ) = min(θ, big_angle_pivot − θ): 30° and 110° score alike.
constexpr double big_angle_pivot = 140;

// atan2 for y >= 0 in degrees, to within 1e-4 degrees (the polynomial's
// largest error on [0, 1] is 9.6e-5 degrees): a minimax polynomial
// for atan on [0, 1] and the identities atan x = 90° − atan(1/x),
// atan2(y, −x) = 180° − atan2(y, x).  Used for the search's objective only;
// the monotone rule compares triangle_angles (quality.hpp), the reported ones.
constexpr double fast_atan2_error_deg = 1e-4;
inline double fast_atan2_deg(double y, double x) {
    const double ax = std::abs(x);
    const bool swap = y > ax;
    const double r = swap ? ax / y : (ax > 0 ? y / ax : 0);
    const double r2 = r * r;
    double a = r * (0.99997726 + r2 * (-0.33262347 + r2 * (0.19354346 + r2 * (-0.11643287 + r2 * (0.05265332 + r2 * -0.01172120)))));
    a *= deg_per_rad;
    if (swap) a = 90 - a;
    return x < 0 ? 180 - a : a;
}

// A triangle's smallest and largest angle and quality min(θmin, pivot − θmax)
// (g is a tent, so the middle angle never scores below the two extremes),
// from the fast atan2: each within 3·fast_atan2_error_deg (θc = 180° − θa − θb).
struct FastQ {
    double min_deg, max_deg, q;
};
inline FastQ tri_fast(Vec2 a, Vec2 b, Vec2 c) {
    const Vec2 ab = b - a, bc = c - b, ca = a - c;
    const double x = std::abs(cross(ab, c - a));
    const double ta = fast_atan2_deg(x, -dot(ab, ca)), tb = fast_atan2_deg(x, -dot(bc, ab));
    const double tc = 180 - ta - tb;
    const double mn = std::min({ta, tb, tc}), mx = std::max({ta, tb, tc});
    return {mn, mx, std::min(mn, big_angle_pivot - mx)};
}
inline double tri_q_fast(Vec2 a, Vec2 b, Vec2 c) { return tri_fast(a, b, c).q; }

}  // namespace warpmesh::plane
