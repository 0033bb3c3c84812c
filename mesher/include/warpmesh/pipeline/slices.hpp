// slices.hpp — meshing a range of slices of one volume (`--slices k=0:113`).
//
// The volume is read once by the caller; mesh_slices loads each slice of the
// range (load_slice), hands it to the caller's `mesh_one`, which meshes it and
// writes what it wants, and collects one summary line per slice.  Slices are
// processed in parallel (one OpenMP thread each, dynamic schedule); the
// callback must therefore be safe to call concurrently for different slices.
//
// The batch's report (SliceBatch) and its text and JSON are the report
// module's (report/slices_report.hpp).
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
#include "warpmesh/report/report.hpp"
#include "warpmesh/report/slices_report.hpp"  // SliceOutcome, SliceBatch, to_json, to_text, batch_warnings

namespace warpmesh {

// Where a slice lies, for its report (Mesh2dReport::slice: "units", "slice",
// "plane"): a placed slice only (SlicePlacement::placed; a plain image in
// pixel units has none, its report stays what it always was).
std::optional<SliceFigures> slice_figures(const LoadedSlice& slice);

// What the caller reports for one meshed slice.
struct SliceMeshed {
    QualityReport report;
    std::string outputs;                // e.g. "out_060.vtu, out_060.msh" (for the summary), may be empty
    std::vector<std::string> warnings;  // the slice's (MeshResult::warnings), not printed by mesh_one
};

// Mesh slices range.first .. range.end - 1 along range.axis.  `options` is
// used for every slice with its `slice` replaced.  Throws InputError when the
// range reaches beyond the volume, or when every slice is skipped.
SliceBatch mesh_slices(const Volume& volume, const SliceRange& range, const SliceOptions& options,
                       const std::function<SliceMeshed(const LoadedSlice&)>& mesh_one, double read_seconds = 0);

}  // namespace warpmesh
