// slices_report.hpp — the report of a batch of slices (`warpmesh mesh
// --slices k=0:113`, pipeline/slices.hpp: mesh_slices fills it): one outcome
// per slice, as text (one line per slice and a total) and as one JSON object
// (--report FILE).  Formatted by report/slices_report.cpp.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "warpmesh/io/volume.hpp"  // SliceRange
#include "warpmesh/post/quality.hpp"
#include "warpmesh/report/report.hpp"  // SliceFigures

namespace warpmesh {

struct SliceOutcome {
    std::int64_t index = 0;
    std::optional<QualityReport> report;  // set iff the slice was meshed
    std::string outputs;                  // the caller's SliceMeshed::outputs
    std::string skipped;                  // why the slice was skipped (iff no report)
    std::optional<SliceFigures> placed;   // where the slice lies (pipeline/slices.hpp: slice_figures; none unplaced)
    std::vector<std::string> warnings;    // the caller's SliceMeshed::warnings
};

struct SliceBatch {
    std::string input, format;  // file name and format of the volume
    SliceRange range;
    std::vector<SliceOutcome> slices;  // range.first .. range.end - 1, in order
    double read_seconds = 0;           // as passed in by the caller
    double total_seconds = 0;          // read_seconds + the loop's wall time

    std::int64_t meshed() const;
    std::int64_t triangles() const;  // over the meshed slices
};

// The batch summary: JSON (one object: input, format, axis, first, end,
// slices [{index, outputs, triangles, vertices, area, min_angle_deg,
// max_angle_deg, plane[, warnings]} or {index, skipped}], meshed, skipped, triangles,
// read_seconds, total_seconds) and text (one line per slice and a total).
std::string to_json(const SliceBatch& batch);
std::string to_text(const SliceBatch& batch);

// The slices' warnings, each once with the slices that gave it, in the order
// of their first slice: "slice k=4: W" or "slices k=3, 4, 7: W" (a warning
// repeated word for word by many slices is one line).
std::vector<std::string> batch_warnings(const SliceBatch& batch);

}  // namespace warpmesh
