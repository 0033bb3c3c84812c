// triangle_shape.hpp — what is measured of one triangle: its smallest and
// largest angles, its radius ratio, its signed area.  The quality report
// (post/quality.hpp), the optimisation pass and the pictures' colouring by
// angle (io/writers.hpp) all measure with these.
//
// This is the *reporting* path: angles are computed in floating point with
// std::atan2 and are not part of any proof.
#pragma once

#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

// Smallest and largest interior angle of triangle abc, in degrees (either
// orientation).  The smallest angle is opposite the shortest side and the
// largest opposite the longest (law of sines), so only these two are computed,
// each as atan2(|cross|, dot) of the two sides at that vertex — accurate for
// tiny and near-180° angles alike.  Three distinct collinear points give 0 and
// 180; at a repeated vertex atan2(0, 0) = 0 is used.
struct TriangleAngles {
    double min_deg, max_deg;
};
TriangleAngles triangle_angles(Vec2 a, Vec2 b, Vec2 c);
// triangle_angles(a, b, c).min_deg, bit for bit, with one atan2 and no square
// root (the optimisation pass's monotone rule).
double triangle_min_angle(Vec2 a, Vec2 b, Vec2 c);

// Radius ratio normalised so that the equilateral triangle has 1:
//   2 r_in / R_circ = 16 A² / ((a + b + c) a b c) = 4 cross² / ((a + b + c) a b c),
// using r_in = 2A / (a + b + c), R_circ = a b c / (4A) and cross = 2A.  It lies
// in [0, 1]; 0 for degenerate triangles.
double radius_ratio(Vec2 a, Vec2 b, Vec2 c);

// Everything the quality report needs from one triangle, from the squared side
// lengths (no hypot, two atan2): triangle_angles, radius_ratio and the signed
// doubled area (> 0 for counter-clockwise) at once.
struct TriangleShape {
    TriangleAngles angles;
    double ratio;       // 2 r_in / R_circ
    double twice_area;  // signed: > 0 for counter-clockwise
};
TriangleShape triangle_shape(Vec2 a, Vec2 b, Vec2 c);

}  // namespace warpmesh
