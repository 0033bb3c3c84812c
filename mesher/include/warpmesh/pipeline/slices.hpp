// slices.hpp — the slices of a volume as the 2D pipeline's input: one slice
// loaded as a level set or a material field (load_slice, `--slice k=60`),
// and a range of slices meshed (mesh_slices, `--slices k=0:113`).  Where a
// slice lies is io/volume.hpp's (place_slice).
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

#include "warpmesh/io/volume.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/report/report.hpp"
#include "warpmesh/report/slices_report.hpp"  // SliceOutcome, SliceBatch, to_json, to_text, batch_warnings

namespace warpmesh {

// ---------------------------------------------------------------------------
// One slice.

struct SliceOptions {
    // Which slice; none: the only one (k = 0) of a single-slice volume or
    // image, refused for a volume of several slices.
    std::optional<SliceSpec> slice;
    Units units = Units::physical;           // pixels: x = ia, y = ib
    ImageLevelSetOptions levelset;           // threshold or label mode (its geometry is replaced)
    // Multi-material instead of one level set: the label image's materials
    // ("all" or a label list, as make_label_materials reads it), placed in
    // the same units.
    std::optional<std::string> materials;
    // load_slice refuses (InputError naming --max-memory) a slice whose
    // level set or material field would take the resident memory above this
    // (memory.hpp).
    std::uint64_t max_memory = default_max_memory;
};

// A slice ready to mesh: the level set (or with SliceOptions::materials the
// material field) in the slice's 2D coordinates, and where it is.
struct LoadedSlice : SlicePlacement {
    std::unique_ptr<LevelSet> f;                // one region (null with materials)
    std::unique_ptr<MaterialField> materials;   // multi-material (null without)
    int width = 0, height = 0;  // pixels along x and y
    SliceSpec slice;            // which slice (k = 0 for an image)
    std::string format;         // of the file read
};

// The level set (or the materials) of one slice.  Throws InputError for an
// index outside the volume, a slice less than 2 x 2 pixels, label mode or
// materials on values that are not integers in 0..65535, and whatever
// make_image_levelset (make_label_materials) refuses (e.g. an empty region,
// labels absent from the slice).
LoadedSlice load_slice(const Volume& volume, const SliceOptions& options);

// The level set of an input file: read_volume, then load_slice.
LoadedSlice load_level_set(const std::string& path, const SliceOptions& options, const VolumeLimits& limits = {});

// The slice as a 16-bit image in pixel units, placed as load_slice places
// it with Units::pixels: its first in-plane index axis along the columns, its
// second upwards (row 0 at the top, y = rows - 1 - row).  For label images
// (Python's read_image; place_slice gives where its pixels lie).  maxval:
// the volume's, else the largest sample (at least 1).  Throws InputError as
// load_slice for the slice, and for a sample that is not an integer in
// 0..65535.
Image slice_image(const Volume& volume, const std::optional<SliceSpec>& slice);

// Where a slice lies, for its report (Mesh2dReport::slice: "units", "slice",
// "plane"): a placed slice only (SlicePlacement::placed; a plain image in
// pixel units has none, its report stays what it always was).
std::optional<SliceFigures> slice_figures(const LoadedSlice& slice);

// ---------------------------------------------------------------------------
// A range of slices.


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
