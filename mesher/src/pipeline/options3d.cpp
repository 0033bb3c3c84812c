// options3d.cpp — the options of the 3D mesher by name, and their validation
// (mesh3d_options.hpp).
#include <cmath>
#include <cstdint>
#include <string>

#include "warpmesh/core/grading.hpp"
#include "warpmesh/pipeline/mesh3d_options.hpp"

namespace warpmesh {

namespace {

using O = Option<Mesh3dOptions>;

constexpr std::array<Named<bool>, 2> background_names{{{false, "drop"}, {true, "keep"}}};

// The label distance band in voxels: 2 to 1000 (OptionError otherwise).
int band_in_range(std::int64_t n) {
    if (n < 2 || n > 1000) throw OptionError("band", "{band} must be 2 to 1000 voxels (got " + std::to_string(n) + ")");
    return static_cast<int>(n);
}

O entry(std::string_view name, OptionKind kind, std::string_view metavar, std::string_view help,
        void (*set)(Mesh3dOptions&, const OptionValue&)) {
    O o;
    o.name = name, o.kind = kind, o.metavar = metavar, o.group = "lattice and algorithm", o.help = help, o.set = set;
    return o;
}

std::vector<O> entries() {
    std::vector<O> t;
    t.push_back(entry("spacing", OptionKind::number, "S",
                      "the BCC lattice's cube side, in the input's units (default: the smallest voxel size; required "
                      "for shapes)",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.spacing = v.number(); }));
    t.push_back(entry("face_rule", OptionKind::choice, "",
                      "how the stencils' quads are split: delaunay (the default for one region: each face quad by the "
                      "empty-circle test, at alphas (0.2675, 0.39), certified by proofs/bcc_delaunay.cert) or parity "
                      "(Labelle and Shewchuk's rule at (0.285, 0.3985), certified by proofs/bcc.cert; the default and "
                      "the only rule for several materials, whose two sides of an interface must agree)",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.face_rule = v.choice(face_rule_names); }));
    t.back().choices = words_of(face_rule_names);
    t.push_back(entry("verify", OptionKind::flag, "",
                      "check every tetrahedron against its key's claim in the face rule's certificate (default: "
                      "off in 3D)",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.verify = v.flag(); }));
    t.back().off_flag = "--no-verify";
    t.push_back(entry("band", OptionKind::integer, "N",
                      "label mode: the voxels around the region's boundary within which its signed distance is "
                      "exact (default 4, 2 to 1000); farther it is clamped, as only its sign matters to the mesher "
                      "there, so a wider band costs memory and time and lets the coarse-spacing check measure "
                      "thicker parts",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.band = band_in_range(v.integer()); }));
    t.push_back(entry("manifold", OptionKind::flag, "",
                      "make the boundary manifold where parts of the region touch only at a vertex or along an edge "
                      "(voxel-scale contacts): each such vertex gets a copy per part, at the same place; no "
                      "tetrahedron moves, so the certified bounds hold; the report counts the vertices added and the "
                      "non-manifold places left (default: off)",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.manifold = v.flag(); }));
    t.push_back(entry("background", OptionKind::choice, "",
                      "with several materials: output the background's tetrahedra too, region 0 (keep), or not "
                      "(drop, default; it still bounds the materials)",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.keep_background = v.choice(background_names); }));
    t.back().group = "input (materials)";
    t.back().choices = words_of(background_names);
    t.push_back(entry("graded", OptionKind::flag, "",
                      "graded mesh on a 2:1-balanced octree: the lattice's spacing along the surface (and every "
                      "interface of several materials), cells up to {max_size} (default: as coarse as the region "
                      "allows) inside and outside, joined by transition tetrahedra certified by proofs/bcc_graded.cert",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.graded = v.flag(); }));
    t.push_back(entry("max_size", OptionKind::number, "H",
                      "every tetrahedron's longest edge at most H (input units; H >= 2 * spacing); graded: caps the "
                      "octree's cells; uniform: checked",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.max_size = v.number(); }));
    t.push_back(entry("grading", OptionKind::number, "G",
                      "graded, 1.1 <= G <= 2 (default 2: 2:1 balance): cell sizes grow away from the surface by at "
                      "most a factor G per cell on average",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.grading = v.number(); }));
    t.push_back(entry("max_memory", OptionKind::integer, "MB",
                      "refuse, before the work, inputs whose reading or meshing would take more than about MB "
                      "megabytes (default 2048)",
                      [](Mesh3dOptions& o, const OptionValue& v) { o.max_memory = v.megabytes(); }));
    return t;
}

}  // namespace

void validate(const Mesh3dOptions& o, const GivenOptions& given) {
    if (o.spacing && !(*o.spacing > 0 && std::isfinite(*o.spacing)))
        throw OptionError("spacing", "{spacing} must be positive and finite (got " + number_text(*o.spacing) + ")");
    band_in_range(o.band);
    if (o.max_size && !(*o.max_size > 0 && std::isfinite(*o.max_size)))
        throw OptionError("max_size", "{max_size} must be positive and finite (got " + number_text(*o.max_size) +
                                          "; leave it out for no size bound)");
    if (o.spacing && o.max_size) check_max_size(*o.max_size, *o.spacing);
    if (!(o.grading >= min_grading && o.grading <= max_grading))
        throw OptionError("grading", "{grading} must be between 1.1 and 2 (got " + number_text(o.grading) +
                                         "; 2: neighbouring cells differ by a factor 2 at most; G < 2: sizes grow by at most "
                                         "a factor G per cell on average; the octree's templates allow no more than 2)");
    if (!o.graded && (o.grading != max_grading || given.contains("grading")))
        throw OptionError("grading", "{grading} applies to graded meshes: add {graded=true} (a uniform mesh's size is its spacing)");
}

void check_max_size(double max_size, double spacing) {
    if (max_size >= 2 * spacing) return;
    throw OptionError("max_size", "{max_size} " + number_text(max_size) + " is below 2 * spacing = " + number_text(2 * spacing) +
                                      ": tetrahedra of the surface band reach edges of 2 * spacing; use {spacing=" +
                                      number_text(max_size / 2) + "} or less");
}

const OptionTable<Mesh3dOptions>& mesh3d_option_table() {
    static const OptionTable<Mesh3dOptions> table{entries(), validate};
    return table;
}

}  // namespace warpmesh
