// optimize_report.hpp — what the optimisation pass (optimize.hpp:
// optimize_mesh) reports, apart from the pass so that the report
// (report/report.hpp) needs only this.
#pragma once

#include <cstdint>

namespace warpmesh {

struct OptimizeReport {
    std::int64_t triangles = 0;
    std::int64_t band_triangles = 0;   // triangles with an active vertex
    std::int64_t active_vertices = 0;  // of which fixed: not counted
    std::int64_t moves = 0, flips = 0;
    int sweeps = 0;  // refinement's sweeps included
    // Refinement: bad triangles whose patch was re-triangulated, the vertices
    // it inserted, of which on boundary edges.
    std::int64_t refined_triangles = 0, inserted_vertices = 0, boundary_splits = 0;
    std::int64_t interface_splits = 0;  // inserted on interfaces (materials)
    std::int64_t removed_vertices = 0;  // interior vertices removed (materials; src/post/remove.hpp)
    // Over all triangles of the mesh, degrees.
    double min_angle_before = 0, min_angle_after = 0;
    double max_angle_before = 0, max_angle_after = 0;
    double mean_min_angle_before = 0, mean_min_angle_after = 0;
    // The least certified_min_angle of the mesh, else options.certified_floor.
    double certified_floor = 0;
    // The largest distance of a level-set boundary edge to f = 0 (the measure
    // of measure_fidelity), before and after.
    double boundary_distance_before = 0, boundary_distance_after = 0;
    double seconds = 0;
};

}  // namespace warpmesh
