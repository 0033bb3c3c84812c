// material_stats.hpp — the figures of one material of a multi-material mesh
// and of one junction square (materials.hpp: MaterialResult), apart from the
// mesher so that the report (report/report.hpp) needs only these.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "warpmesh/mesh2d/generic_square.hpp"  // MaterialCorner

namespace warpmesh {

struct MaterialStats {
    std::int32_t tag = 0;
    std::string name;
    bool output = true;            // false: the dropped background
    std::int64_t triangles = 0;    // of the full tiling (also when not output)
    double area = 0;               // of those triangles
    double perimeter = 0;          // length of its interfaces, boundary and domain border
    std::optional<double> reference_area;
    // With --optimize: its area before the pass (the report's
    // "area_before_optimize"; with reference_area, its error may not grow).
    std::optional<double> area_before_optimize;
    // Size caps (mesh(const MaterialField&, ...) with MeshOptions::max_size_of):
    // its cap, if it has one; the longest edge of its output triangles, once
    // measure_longest_edges ran.  Reported only when some material has a cap.
    std::optional<double> max_size;
    double longest_edge = 0;
};

struct JunctionSquare {
    std::int64_t i, j;
    std::array<std::int32_t, 4> tags;  // corner materials A, B, C, D
    std::string pattern;               // its junction key, e.g. "aRaUbscs": corners' partition letters and warps
    std::array<MaterialCorner, 4> key{};  // the same key: letters (material classes 0..3) and warps
    double min_deg = 0, max_deg = 0;   // the key's certified bounds (every angle of its triangles in between; certification's)
};

}  // namespace warpmesh
