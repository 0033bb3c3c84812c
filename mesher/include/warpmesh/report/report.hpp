// report.hpp — the reports, formatted: what `warpmesh mesh` prints (text)
// and writes with --report FILE (one JSON object), for the pipeline, the
// command line and the Python module.  The figures come from elsewhere: the
// quality measurement (quality.hpp: compute_quality), the certification
// (certified.hpp: CertifiedSummary), the multi-material mesher
// (materials.hpp: MaterialResult), the optimisation pass (optimize.hpp); this
// module only turns them into text.
//
// The JSON report of a mesh is quality_json's fields in a fixed order, then
// QualityReport::extra: (key, value) pairs, the value already JSON text
// (json_string, json_number, or an object/array written with them).  To add
// a field, append a pair to the extra fields where the figure is known
// (pipeline.cpp), or add it to the section's *_json function here, and its
// line to the matching *_text function.  Values are written with the
// shortest round-trip form (json_number), non-finite ones as null.
//
// Only declarations of the reported types are needed here, so any header may
// include this one.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace warpmesh {

struct QualityReport;             // quality.hpp
struct CertifiedSummary;          // certified.hpp
struct MaterialResult;            // materials.hpp
struct MeshResult;                // pipeline.hpp
enum class DiagonalRule : std::uint8_t;  // generic_square.hpp
enum class LatticeMetric : std::uint8_t;  // generic_square.hpp

// ---- JSON values ------------------------------------------------------------------
// A quoted, escaped string / a number (shortest round-trip form; null when not
// finite) / an integer.
std::string json_string(std::string_view s);
std::string json_number(double x);
std::string json_number(std::int64_t i);

// Further JSON fields, in order: key → JSON value text, e.g.
// {"lattice", "[1024, 768]"}, {"rule", json_string("max-min")}.
using ReportFields = std::vector<std::pair<std::string, std::string>>;

// The diagonal rule's name in reports and on the command line: "maxmin",
// "separating", "fan".
const char* rule_name(DiagonalRule rule);

// ---- the quality report (quality.hpp) ------------------------------------------------
// Human-readable summary, several lines, ends with a newline.
std::string quality_text(const QualityReport& report);

// One JSON object: every field of QualityReport, then report.extra, then
// `extra`.
std::string quality_json(const QualityReport& report, const ReportFields& extra = {});

// quality_json written atomically to `path` (throws OutputError).
void write_quality_json(const std::string& path, const QualityReport& report, const ReportFields& extra = {});

// ---- the certification (certified.hpp) -------------------------------------------------
// The "certified" object of the JSON report: the certified bounds, the
// warped squares (flat, not flat, with the first not-flat examples), the
// rule's theorem, and the boundary fidelity when measured; `junctions`
// (multi-material meshes) adds the count of junction squares; `metric` the
// lattice whose theorem it is (rhombic: proofs/rhombic_<rule>.cert).
std::string certified_json(const CertifiedSummary& cert, DiagonalRule rule, bool junctions, LatticeMetric metric);
// Its lines of the text report.
std::string certified_text(const CertifiedSummary& cert, DiagonalRule rule, LatticeMetric metric);

// ---- multi-material meshes (materials.hpp) -----------------------------------------------
// JSON members ("materials": [...], "junction_squares": ..., ...) and text
// lines; `warnings` receives one line per material that got no triangle (it
// is lost at this spacing).  With a cap on some material
// (MaterialStats::max_size), each material's entry adds "max_size" (null
// without) and "longest_edge", its text line "longest edge L (max size H)".
ReportFields material_report_json(const MaterialResult& r);
std::string material_report_text(const MaterialResult& r, std::vector<std::string>* warnings = nullptr);

// ---- a mesh result (pipeline.hpp) ----------------------------------------------------
// The report as one JSON object (what `warpmesh mesh --report` writes) and as
// text (what the command line prints): the quality, the certification's lines,
// the materials' lines, the optimisation pass's lines.
std::string to_json(const MeshResult& result);
std::string to_text(const MeshResult& result);

// The 3D report: report3d.hpp.

}  // namespace warpmesh
