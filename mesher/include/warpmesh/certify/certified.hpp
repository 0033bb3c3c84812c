// certified.hpp — the proofs' per-key angle bounds, compiled into the mesher,
// and the per-square certification of a mesh against them.
//
// The table is generated at configure time from the `key ` lines of
// proofs/maxmin.cert and proofs/separating.cert (mesher/CMakeLists.txt →
// build/mesher/generated/certified_table.cpp); a change of a certificate
// re-runs the configuration.  Format of a line (proofs/README.md):
//   key <index> <code> <flat 0|1> <m> <qmin> <qmax> <leaves>
// meaning: for every configuration of the key, every angle a of both chosen
// triangles has qmax <= cot(a) <= qmin.
//
// The proof is about the cotangents (min_cot = qmax, max_cot = qmin, rationals
// rounded to the nearest double); the degrees are atan-derived and for
// reporting only.
//
// The rhombic lattice (LatticeMetric::rhombic) has its own tables, from
// proofs/rhombic_maxmin.cert and proofs/rhombic_separating.cert, looked up
// only with that metric: their bounds are on r = dot / cross of the rhombic
// forms (triangle_forms(..., rhombic)) = sqrt(3) cot(angle), in lattice
// coordinates; min_cot / max_cot hold r there, the degrees are the physical
// angles.  The fan rule has no rhombic table (null bounds, no keys).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "warpmesh/mesh2d/generic_square.hpp"
#include "warpmesh/mesh2d/square_keys.hpp"  // key_code, junction keys, flatness

namespace warpmesh {

// Only named below (the report includes this header, and needs none of them).
struct Lattice;     // levelset/levelset.hpp
class LevelSet;     // levelset/levelset.hpp
struct Mesh;        // core/mesh.hpp
struct Vec2;        // core/mesh.hpp
struct SquareKeys;  // mesh2d/lattice.hpp

struct CertifiedBound {
    double min_deg, max_deg;   // arccot(max_cot), arccot(min_cot): every angle in [min_deg, max_deg]
    double min_cot, max_cot;   // qmax, qmin of the key line: min_cot <= cot(angle) <= max_cot (rhombic: r)
    bool flat_compatible;
};

// The bound of the key, or nullptr if the key is not in the compiled-in table.
const CertifiedBound* certified_bound(DiagonalRule rule, const std::array<CornerState, 4>& corners,
                                      LatticeMetric metric = LatticeMetric::square);

// True when the build found both certificates of the metric (maxmin and
// separating: the tables are non-empty).
bool certified_table_available(LatticeMetric metric = LatticeMetric::square);
// Number of keys of the compiled-in table for a rule.
std::size_t certified_key_count(DiagonalRule rule, LatticeMetric metric = LatticeMetric::square);

// The theorems as implied by the table: over all keys ("any") and over the
// flat-compatible keys only ("flat"), the least min_deg and the greatest
// max_deg (every angle lies in [min_deg, max_deg]).
struct CertifiedTheorem {
    double min_deg_any, min_deg_flat;
    double max_cot_any, max_cot_flat;  // the largest cot bound, behind min_deg (proof side)
    double max_deg_any, max_deg_flat;
};
CertifiedTheorem certified_theorem(DiagonalRule rule, LatticeMetric metric = LatticeMetric::square);

// Junction keys (square_keys.hpp), certified by proofs/materials.cert (the
// separating rule) and proofs/materials_fan.cert (the fan rule).
// The bound of a junction key (letters as junction_letters gives them) under
// `rule` (separating or fan), or nullptr if it is not in the rule's
// compiled-in table (maxmin: none, the rule is refused with materials).
const CertifiedBound* certified_junction_bound(const std::array<MaterialCorner, 4>& letters,
                                               DiagonalRule rule = DiagonalRule::separating);
std::size_t certified_junction_key_count(DiagonalRule rule = DiagonalRule::separating);
// The theorem over the junction keys (the *_flat members are unused: NaN).
CertifiedTheorem certified_junction_theorem(DiagonalRule rule = DiagonalRule::separating);

// ---- the table as text, and its comparison with a certificate --------------
// One parsed key line.
struct CertKeyLine {
    std::int64_t index = 0;
    std::string code;
    bool flat = false;
    int m = 0;
    std::string qmin, qmax;  // the rationals as written
};
// The compiled-in `key ` lines of a rule (the generated file's text), and
// those of its junction keys (proofs/materials.cert, materials_fan.cert).
std::string_view certified_table_text(DiagonalRule rule, LatticeMetric metric = LatticeMetric::square);
std::string_view certified_junction_table_text(DiagonalRule rule = DiagonalRule::separating);
// Parse `key ` lines (other lines are ignored); throws std::runtime_error on a
// malformed key line.
std::vector<CertKeyLine> parse_cert_key_lines(std::string_view text);
// Compares two key lists key by key; returns "" if equal, otherwise a
// description of the first difference.
std::string compare_cert_keys(const std::vector<CertKeyLine>& a, const std::vector<CertKeyLine>& b);
// p/q or an integer → double (via __int128 and long double).
double parse_rational(std::string_view text);

// ---- certification of a mesh -------------------------------------------------
struct CertifyOptions {
    bool enabled = true;    // compute the per-square bounds and the summary
    bool cell_data = true;  // add mesh.cell_data "certified_min_angle"
    bool verify = false;    // check every triangle of a keyed square against its interval
};

// Squares "through the rule" are the finest squares with a warped or
// zero-valued corner that emit a triangle (they have a key).  Other triangles:
// plain lattice squares (45°/90° exactly) and graded coarse-leaf templates
// (right isosceles: 45°/90°), bound [45°, 90°]; on the rhombic lattice the
// plain rhombi split by their short diagonal (equilateral: [60°, 60°]).
struct CertifiedSummary {
    bool available = false;
    double min_deg = 0, max_deg = 0;     // guarantee of the mesh: min / max over its triangles' bounds
    double keyed_min_deg = 0;            // min over the keyed squares only (NaN if none)
    std::int64_t keyed_squares = 0, flat_squares = 0, nonflat_squares = 0;
    std::vector<std::array<std::int64_t, 2>> nonflat_examples;  // up to 20 (i, j)
    std::vector<std::string> nonflat_keys;                     // their keys
    std::vector<std::array<double, 4>> nonflat_boxes;          // all of them (up to 10^5): {xmin, ymin, xmax, ymax}
    bool verified = false;
    // Multi-material meshes: keyed squares whose corners carry 3 or 4
    // materials ("junction squares"), certified by their junction keys
    // (proofs/materials.cert) and included in every count and bound above
    // (they count as non-flat).
    std::int64_t junction_squares = 0;
    std::vector<std::int64_t> junction_list;  // the first 20, as square indices i + j nx
    // Fidelity of the level-set boundary (filled by measure_fidelity).
    bool has_fidelity = false;
    double max_boundary_distance = 0;
    std::int64_t boundary_edges_off_levelset = 0;
};

// The certification of a 2D mesh from the keys its mesher recorded
// (mesh2d/lattice.hpp: SquareKeys, in their lattice metric: its
// certificates' tables, its forms for verify, in lattice coordinates, and
// its plain triangles — square: 45-45-90; rhombic: equilateral): every keyed
// square's key looked up (a junction square's among the junction keys), its
// triangles given its bound (cell data "certified_min_angle" with
// options.cell_data) and, with options.verify, checked against it; every
// other triangle is a plain lattice or template triangle.  Throws
// std::logic_error (→ internal error) for an unknown key or, with verify, for
// a triangle outside its interval.  An empty summary (available false)
// without options.enabled or without the metric's certificates in this
// build.
CertifiedSummary certify_keys(Mesh& mesh, const Lattice& lattice, const SquareKeys& keys, DiagonalRule rule,
                              const CertifyOptions& options);

// The largest distance from the mesh's level-set boundary edges to f = 0,
// sampled at 9 points per edge (endpoints included) as |f| / |grad f| with a
// central-difference gradient (step 1e-6 s); and the number of such edges with
// an endpoint where |f| > 1e-9 s.  Meaningful for analytic shapes.
void measure_fidelity(const Mesh& mesh, const LevelSet& f, double spacing, CertifiedSummary& summary);

// The distance measure of measure_fidelity for one edge a-b: the largest
// |f| / |grad f| at its 9 sample points.
double edge_distance_to_levelset(const LevelSet& f, Vec2 a, Vec2 b, double spacing);

}  // namespace warpmesh
