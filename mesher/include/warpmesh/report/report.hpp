// report.hpp — the reports: what the pipelines measured, as typed structs,
// and the one place that turns them into text (what `warpmesh mesh` and
// `warpmesh mesh3d` print) and JSON (what --report FILE writes, what the
// Python module's report dict holds).  The figures come from their stages:
// the quality measurement (quality.hpp: compute_quality), the certification
// (certified.hpp: CertifiedSummary), the multi-material mesher
// (material_stats.hpp: MaterialStats, JunctionSquare), the optimisation pass
// (optimize_report.hpp: OptimizeReport), the 3D pipeline (mesh3d.hpp:
// Mesh3dReport).  It includes only the headers of these figures, not their
// stages' (many files include it, through pipeline/mesh2d.hpp).  The 2D pipeline (pipeline/mesh2d.hpp: mesh()) fills a
// Mesh2dReport, the 3D one a Mesh3dReport; this module only formats them.
//
// The JSON report of a 2D mesh is one object: the quality's fields in a
// fixed order (quality_json), then the stages' fields in pipeline order (see
// Mesh2dReport).  To add a field: a member in the stage's struct below, filled
// where the figure is known (the pipeline), written by to_json/to_text of
// Mesh2dReport (report2d.cpp).  Values are written with the shortest
// round-trip form (json_number), non-finite ones as null.  A batch of slices
// has its own report (slices_report.hpp).
//
// The report layer sits above core, certify, mesh2d, mesh3d and post, and
// below the pipelines: it includes none of pipeline/.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "warpmesh/certify/certified.hpp"       // CertifiedSummary
#include "warpmesh/mesh2d/generic_square.hpp"    // DiagonalRule, LatticeMetric
#include "warpmesh/mesh2d/material_stats.hpp"    // MaterialStats, JunctionSquare
#include "warpmesh/post/optimize_report.hpp"     // OptimizeReport
#include "warpmesh/post/quality.hpp"             // QualityReport

namespace warpmesh {


// ---- JSON values ------------------------------------------------------------------
// A quoted, escaped string / a number (shortest round-trip form; null when not
// finite) / an integer.
std::string json_string(std::string_view s);
std::string json_number(double x);
std::string json_number(std::int64_t i);

// JSON fields in order, key → JSON value text: how report3d.cpp lists the
// 3D report's fields before writing them.
using ReportFields = std::vector<std::pair<std::string, std::string>>;

// The diagonal rule's name in reports and on the command line: "maxmin",
// "separating", "fan".
const char* rule_name(DiagonalRule rule);

// ---- the quality report (quality.hpp) ------------------------------------------------
// Human-readable summary, several lines, ends with a newline.
std::string quality_text(const QualityReport& report);

// One JSON object: every field of QualityReport (the first fields of a 2D
// mesh's report).
std::string quality_json(const QualityReport& report);

// quality_json written atomically to `path` (throws OutputError).
void write_quality_json(const std::string& path, const QualityReport& report);

// ---- the certification (certified.hpp) -------------------------------------------------
// The "certified" object of the JSON report: the certified bounds, the
// warped squares (flat, not flat, with the first not-flat examples), the
// rule's theorem, and the boundary fidelity when measured; `junctions`
// (multi-material meshes) adds the count of junction squares; `metric` the
// lattice whose theorem it is (rhombic: proofs/rhombic_<rule>.cert).
std::string certified_json(const CertifiedSummary& cert, DiagonalRule rule, bool junctions, LatticeMetric metric);
// Its lines of the text report.
std::string certified_text(const CertifiedSummary& cert, DiagonalRule rule, LatticeMetric metric);

// ---- the optimisation pass (optimize.hpp) ----------------------------------------------
// Its lines of the text report and its JSON object (the report's "optimize").
std::string optimize_text(const OptimizeReport& report);
std::string optimize_json(const OptimizeReport& report);

// ---- the 2D report (filled by pipeline/mesh2d.hpp's mesh()) ------------------------------
// Each struct is one stage's part; its fields are written in this order.

// What was meshed, on which lattice: "input", "levelset", "rule",
// "spacing", "repeat" (only when > 1), "lattice" ([nx, ny]).
struct LatticeFigures {
    std::string input;     // MeshOptions::input: a path or a shape string
    std::string levelset;  // the level set's (or the material field's) describe()
    DiagonalRule rule = DiagonalRule::separating;
    double spacing = 0;          // of the returned mesh (after Guarantee::flat's halvings)
    std::int64_t repeat = 1;     // benchmark runs; the phase times are the fastest run's
    std::int64_t nx = 0, ny = 0;  // lattice squares
    LatticeMetric metric = LatticeMetric::square;  // rhombic: "lattice_metric" (uniform, one region)
};

// A graded mesh's size control, reported only when the options set one (a
// max size or a grading other than 2: default reports unchanged):
// "max_size" (null: none), "max_cell", "grading", "grading_buffer".
struct SizeControlFigures {
    double max_size = 0;  // 0: none
    std::int64_t max_cell = 0;
    double grading = 2;
    std::int64_t grading_buffer = 0;
};

// One material's size cap (MeshOptions::max_size_of): "max_size_of" entries.
struct MaterialCapFigures {
    std::int32_t tag = 0;
    double max_size = 0;
    std::optional<std::int64_t> max_cell;  // its largest quadtree cell (graded; uniform: null)
};

// The mesher's counts, uniform or graded, one region or materials: "graded",
// "lattice_metric", "leaves_per_level", the size control, "max_size_of",
// "cut_edges", "warped_points", "warped_squares", "separating_overrides",
// "sampled_points".
struct MesherFigures {
    bool graded = false;
    std::vector<std::int64_t> leaves_per_level;       // graded: quadtree leaves per level
    std::optional<SizeControlFigures> size_control;   // graded, when set
    std::vector<MaterialCapFigures> max_size_of;      // materials with a cap (written when some)
    std::int64_t cut_edges = 0, warped_points = 0, warped_squares = 0, separating_overrides = 0;
    std::optional<std::int64_t> sampled_points;       // graded, one region: level-set evaluations
};

// Multi-material meshes (materials.hpp: MaterialResult's figures, those of the
// output mesh): "materials" (per material; with a cap on some material each
// entry adds "max_size" (null without) and "longest_edge"),
// "materials_without_triangles" (material_warnings), "interface_edges",
// "third_material_edges", "centroid_material_triangles", "mixed_triangles",
// "junction_squares" (count, certified, the first examples).
struct MaterialsFigures {
    std::vector<MaterialStats> materials;  // index = material number
    std::int64_t interface_edges = 0, third_material_edges = 0, centroid_material_triangles = 0, mixed_triangles = 0;
    std::int64_t junction_squares = 0;
    std::vector<JunctionSquare> junction_examples;  // the first 20
    bool junctions_certified = false;               // certification ran (with certificates)
};

// The certification's part: with `requested` (MeshOptions::certify) the
// "certified" field, null when the build has no certificates
// (summary.available false); without, no field at all.
struct CertificationFigures {
    bool requested = false;
    bool junctions = false;    // multi-material: the junction squares' count
    CertifiedSummary summary;  // the certification's summary (boxes not needed here)
};

// Where a slice of a volume lies (volume.hpp: a placed LoadedSlice;
// pipeline/slices.hpp: slice_figures): "units", "slice" ({axis, index,
// format}), "plane" ({origin, x_axis, y_axis, normal}), after every other
// field; the slice batch's "plane" too.
struct SliceFigures {
    std::string units;  // "mm" or "pixels"
    int axis = 2;       // 0, 1, 2: i, j, k
    std::int64_t index = 0;
    std::string format;  // of the file read
    std::array<double, 3> origin{}, x_axis{}, y_axis{}, normal{};
};

// The report of one 2D mesh, in the order of its JSON fields: the quality,
// then the lattice, the mesher, the optimisation pass, the materials, the
// process's peak memory, Guarantee::flat's refinements, the certification,
// the slice's placement.  The text: the quality's lines, the certification's
// (when certified), the materials', the optimisation pass's.
struct Mesh2dReport {
    QualityReport quality;  // the output mesh's measurement, with the phase times
    LatticeFigures lattice;
    MesherFigures mesher;
    std::optional<OptimizeReport> optimize;      // with MeshOptions::optimize
    std::optional<MaterialsFigures> materials;   // multi-material meshes
    double peak_memory_mb = 0;                   // the process's peak resident memory
    std::optional<std::int64_t> refinements;     // Guarantee::flat: the spacing's halvings
    CertificationFigures certified;
    std::optional<SliceFigures> slice;           // a placed slice of a volume
};

std::string to_json(const Mesh2dReport& report);
std::string to_text(const Mesh2dReport& report);

// One warning per material with pixels (or an analytic one) that got no
// triangle: it is lost at this spacing (the dropped background may well be
// empty).  These are "materials_without_triangles".
std::vector<std::string> material_warnings(const MaterialsFigures& materials);

// The 3D report: report3d.hpp.

}  // namespace warpmesh
