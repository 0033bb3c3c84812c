// plane.hpp (internal) — the few vector operations on Vec2, and the key of
// an undirected edge, that the optimisation pass and its local refinement
// share.
#pragma once

#include <cstdint>
#include <utility>

#include "warpmesh/mesh.hpp"

namespace warpmesh::plane {

inline Vec2 operator-(Vec2 p, Vec2 q) { return {p.x - q.x, p.y - q.y}; }
inline Vec2 operator+(Vec2 p, Vec2 q) { return {p.x + q.x, p.y + q.y}; }
inline Vec2 operator*(double a, Vec2 p) { return {a * p.x, a * p.y}; }
inline double dot(Vec2 u, Vec2 v) { return u.x * v.x + u.y * v.y; }
inline double cross(Vec2 u, Vec2 v) { return u.x * v.y - u.y * v.x; }
inline double norm2(Vec2 u) { return dot(u, u); }
inline Vec2 perp(Vec2 u) { return {-u.y, u.x}; }

// The edge {a, b} in either orientation.
inline std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace warpmesh::plane
