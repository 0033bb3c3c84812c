// slices.hpp — meshing a range of slices of one volume (`--slices k=0:113`).
//
// The volume is read once by the caller; mesh_slices loads each slice of the
// range (load_slice), hands it to the caller's `mesh_one`, which meshes it and
// writes what it wants, and collects one summary line per slice.  Slices are
// processed in parallel (one OpenMP thread each, dynamic schedule); the
// callback must therefore be safe to call concurrently for different slices.
//
// A slice that cannot be meshed for a reason of its own — load_slice or
// mesh_one throws InputError (an empty region, a slice too small) — is
// *skipped*: its outcome carries the message and the batch goes on.  Any
// other exception (OutputError, an internal error, bad_alloc) is rethrown
// after the loop, the first in slice order.  A batch in which every slice is
// skipped throws InputError naming the first slice's reason.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "warpmesh/post/quality.hpp"
#include "warpmesh/io/volume.hpp"

namespace warpmesh {

// What the caller reports for one meshed slice.
struct SliceMeshed {
    QualityReport report;
    std::string outputs;                // e.g. "out_060.vtu, out_060.msh" (for the summary), may be empty
    std::vector<std::string> warnings;  // the slice's (MeshResult::warnings), not printed by mesh_one
};

struct SliceOutcome {
    std::int64_t index = 0;
    std::optional<QualityReport> report;  // set iff the slice was meshed
    std::string outputs;                  // the caller's SliceMeshed::outputs
    std::string skipped;                  // why the slice was skipped (iff no report)
    std::string plane;                    // the slice's placement, JSON (see slice_report_fields)
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

// Mesh slices range.first .. range.end - 1 along range.axis.  `options` is
// used for every slice with its `slice` replaced.  Throws InputError when the
// range reaches beyond the volume, or when every slice is skipped.
SliceBatch mesh_slices(const Volume& volume, const SliceRange& range, const SliceOptions& options,
                       const std::function<SliceMeshed(const LoadedSlice&)>& mesh_one, double read_seconds = 0);

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
