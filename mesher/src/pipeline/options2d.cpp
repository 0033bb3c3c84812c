// options2d.cpp — the options of the 2D pipeline by name, and their
// validation (mesh2d.hpp: mesh2d_option_table, validate).
#include <cmath>
#include <sstream>

#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"

namespace warpmesh {

namespace {

[[noreturn]] void fail(const char* option, std::string message) { throw OptionError(option, std::move(message)); }

constexpr std::array<Named<Guarantee>, 2> guarantee_names{{{Guarantee::any, "any"}, {Guarantee::flat, "flat"}}};
constexpr std::array<Named<bool>, 2> background_names{{{false, "drop"}, {true, "keep"}}};

using O = Option<MeshOptions>;

O entry(std::string_view name, OptionKind kind, std::string_view metavar, std::string_view group, std::string_view help,
        void (*set)(MeshOptions&, const OptionValue&)) {
    O o;
    o.name = name, o.kind = kind, o.metavar = metavar, o.group = group, o.help = help, o.set = set;
    return o;
}

constexpr std::string_view lattice_group = "lattice and algorithm", certificates = "certificates",
                           input = "input (images)", output = "output";

std::vector<O> entries() {
    std::vector<O> t;
    t.push_back(entry("spacing", OptionKind::number, "S", lattice_group,
                      "lattice spacing, in the input's units: mm for physical inputs (default: the smaller pixel "
                      "size), else pixels (default 1)",
                      [](MeshOptions& o, const OptionValue& v) { o.spacing = v.number(); }));
    O& rule = t.emplace_back(entry(
        "rule", OptionKind::choice, "RULE", lattice_group,
        "fan (default): separating, but a square whose corners are all inside and whose diagonals both have an "
        "angle below atan(1/3) = 18.43 deg gets 4 triangles around its centroid: every angle certified in "
        "[18.4349, 143.1302] deg on every input (uniform and {graded} meshes, one region or several materials); "
        "separating: the mesh boundary follows the level set, certified [14.9999, 143.1302] deg (18.4349 where every "
        "warped square is flat); maxmin: the diagonal with the larger minimum angle (one region); with "
        "{lattice=rhombic} the default is separating",
        [](MeshOptions& o, const OptionValue& v) { o.rule = v.choice(diagonal_rule_names); }));
    rule.choices = words_of(diagonal_rule_names), rule.flag = "--diagonal";
    t.push_back(entry(
        "lattice", OptionKind::choice, "", lattice_group,
        "square (default) or rhombic: the 60-degree rhombic lattice (interior triangles equilateral, edges of length "
        "{spacing}): lower error per unknown, lower certified bounds (proofs/rhombic_*.cert: separating [10.8933, "
        "158.2133] deg, maxmin [12.8294, 150.0200] deg); uniform one-region meshes, {rule} separating or maxmin",
        [](MeshOptions& o, const OptionValue& v) { o.lattice = v.choice(lattice_metric_names); }));
    t.back().choices = words_of(lattice_metric_names);
    t.push_back(entry("graded", OptionKind::flag, "", lattice_group,
                      "graded mesh on a 2:1-balanced quadtree: finest along the boundary (with several materials: "
                      "along every interface)",
                      [](MeshOptions& o, const OptionValue& v) { o.graded = v.flag(); }));
    t.push_back(entry("max_cell", OptionKind::integer, "K", lattice_group,
                      "graded: largest cell, K lattice squares wide (a power of two; default: as coarse as the "
                      "domain allows)",
                      [](MeshOptions& o, const OptionValue& v) { o.max_cell = v.integer(); }));
    t.push_back(entry("max_size", OptionKind::number, "H", lattice_group,
                      "every triangle's longest edge at most H (input units; H >= sqrt(5) * spacing); graded: caps "
                      "the cells (the smaller of this and {max_cell} wins); uniform: the spacing already bounds it "
                      "(checked)",
                      [](MeshOptions& o, const OptionValue& v) { o.max_size = v.number(); }));
    t.push_back(entry("max_size_of", OptionKind::pairs, "T=H", lattice_group,
                      "with several materials: the triangles of material T (its label or tag) have their longest "
                      "edge at most H (rules as {max_size}; the smaller of the two wins; repeatable, each T once; "
                      "graded: caps that material's cells; uniform: checked)",
                      [](MeshOptions& o, const OptionValue& v) { o.max_size_of.push_back(v.tag_and_number()); }));
    t.push_back(entry("grading", OptionKind::number, "G", lattice_group,
                      "graded, 1.1 <= G <= 2 (default 2: 2:1 balance): cell sizes grow away from the boundary by at "
                      "most a factor G per cell on average ({grading} and {max_cell} need {graded}; {max_size} and "
                      "{max_cell} need a positive value: leave them out for no bound)",
                      [](MeshOptions& o, const OptionValue& v) { o.grading = v.number(); }));
    t.push_back(entry("max_squares", OptionKind::integer, "N", lattice_group,
                      "refuse lattices with more than N squares (default 1073741824)",
                      [](MeshOptions& o, const OptionValue& v) { o.max_squares = v.integer(); }));
    t.push_back(entry("optimize", OptionKind::flag, "", lattice_group,
                      "after meshing, move the boundary band's vertices (boundary ones along the level set, "
                      "interface ones along their interface) and flip its interior edges to raise the worst angles; "
                      "no triangle's star gets a smaller minimum angle (materials: no label's area error grows, "
                      "junctions stay put)",
                      [](MeshOptions& o, const OptionValue& v) { o.optimize = v.flag(); }));
    t.push_back(entry("verify", OptionKind::flag, "", certificates,
                      "check every triangle of a warped square against its key's certified angle interval (default: "
                      "on); a violation is an internal error (exit code 3), naming the square",
                      [](MeshOptions& o, const OptionValue& v) { o.verify = v.flag(); }));
    t.back().off_flag = "--no-verify";
    t.push_back(entry("certify", OptionKind::flag, "", certificates,
                      "the per-square certified bounds (default: on; off: no certified_min_angle, no certified "
                      "bounds in the report)",
                      [](MeshOptions& o, const OptionValue& v) { o.certify = v.flag(); }));
    t.back().off_flag = "--no-certify";
    t.push_back(entry("guarantee", OptionKind::choice, "", certificates,
                      "flat: halve the spacing until every warped square's 12-point stencil is flat (theorem F "
                      "applies); any (default): no refinement",
                      [](MeshOptions& o, const OptionValue& v) { o.guarantee = v.choice(guarantee_names); }));
    t.back().choices = words_of(guarantee_names);
    t.push_back(entry("min_spacing", OptionKind::number, "S", certificates,
                      "{guarantee=flat} stops before the spacing drops below S (default: spacing/16)",
                      [](MeshOptions& o, const OptionValue& v) { o.min_spacing = v.number(); }));
    t.push_back(entry("max_memory", OptionKind::integer, "MB", input,
                      "refuse, before the work, inputs whose reading or meshing would take more than about MB "
                      "megabytes (default 2048)",
                      [](MeshOptions& o, const OptionValue& v) { o.max_memory = v.megabytes(); }));
    t.push_back(entry("background", OptionKind::choice, "", input,
                      "with several materials: output the background's triangles (keep) or not (drop, default; it "
                      "still bounds the materials)",
                      [](MeshOptions& o, const OptionValue& v) { o.keep_background = v.choice(background_names); }));
    t.back().choices = words_of(background_names);
    t.push_back(entry("repeat", OptionKind::integer, "N", output,
                      "(benchmarks) mesh N times in this process and report the fastest run's phase times; the mesh "
                      "is the same every time",
                      [](MeshOptions& o, const OptionValue& v) { o.repeat = v.integer(); }));
    return t;
}

// A size bound H (max_size, max_size_of's; `what` names it, marked).
void check_size(double h, double spacing, const char* option, const std::string& what) {
    if (!(h > 0) || !std::isfinite(h)) fail(option, what + " must be positive and finite (got " + number_text(h) + ")");
    if (h < std::sqrt(5.0) * spacing) {
        std::ostringstream m;
        m << what << " " << h << " is below sqrt(5) * spacing = " << std::sqrt(5.0) * spacing
          << ": triangles of the boundary band reach edges of sqrt(5) * spacing; use {spacing="
          << h / std::sqrt(5.0) << "} or less";
        fail(option, m.str());
    }
}

// Each option's range.
void check_values(const MeshOptions& o, const GivenOptions& given) {
    if (!(o.spacing > 0) || o.spacing > 1e9) fail("spacing", "{spacing} must be positive and at most 1e9 (got " + number_text(o.spacing) + ")");
    if (o.max_cell < 0 || (o.max_cell & (o.max_cell - 1)) != 0 || (o.max_cell == 0 && given.contains("max_cell")))
        fail("max_cell", "{max_cell} must be a power of two >= 1, in lattice squares (got " + std::to_string(o.max_cell) +
                             "; leave it out for cells as coarse as the domain allows)");
    if (o.max_size == 0 && given.contains("max_size"))
        fail("max_size", "{max_size} must be positive and finite (leave it out for no size bound)");
    if (o.max_size != 0) check_size(o.max_size, o.spacing, "max_size", "{max_size}");
    for (std::size_t k = 0; k < o.max_size_of.size(); ++k) {
        const std::int32_t tag = o.max_size_of[k].first;
        check_size(o.max_size_of[k].second, o.spacing, "max_size_of", "{max_size_of} " + std::to_string(tag) + "=H: H");
        for (std::size_t q = 0; q < k; ++q)
            if (o.max_size_of[q].first == tag)
                fail("max_size_of", "{max_size_of}: material " + std::to_string(tag) + " is given twice");
    }
    if (!(o.grading >= min_grading && o.grading <= max_grading))
        fail("grading", "{grading} must be between 1.1 and 2 (got " + number_text(o.grading) +
                            "; 2: neighbouring cells differ by a factor 2 at most; G < 2: sizes grow by at most a "
                            "factor G per cell on average; a quadtree's templates allow no more than 2)");
    if (o.min_spacing && !(*o.min_spacing > 0))
        fail("min_spacing", "{min_spacing} must be positive (got " + number_text(*o.min_spacing) + ")");
    if (o.max_squares < 1) fail("max_squares", "{max_squares} must be positive (got " + std::to_string(o.max_squares) + ")");
    if (o.repeat < 1 || o.repeat > 1000) fail("repeat", "{repeat} expects 1 to 1000 (got " + std::to_string(o.repeat) + ")");
}

// Contradictions: options that do not apply with the others are refused, not ignored.
void check_contradictions(const MeshOptions& o, const GivenOptions& given) {
    const char* graded_only = (o.grading != max_grading || given.contains("grading")) ? "grading"
                              : (o.max_cell != 0 || given.contains("max_cell"))    ? "max_cell"
                                                                                    : nullptr;
    if (!o.graded && graded_only)
        fail(graded_only, "{" + std::string(graded_only) +
                              "} applies to graded meshes: add {graded=true} (a uniform mesh's size is its spacing)");
    if (given.contains("min_spacing") && o.guarantee != Guarantee::flat)
        fail("min_spacing", "{min_spacing} applies to {guarantee=flat}");
    if (o.guarantee == Guarantee::flat && !o.certify)
        fail("guarantee", "{guarantee=flat} needs the certification (drop {certify=false})");
    if (o.lattice == LatticeMetric::rhombic) {
        const char* what = o.graded                      ? "{graded=true}"
                           : o.max_size != 0             ? "{max_size}"
                           : o.rule == DiagonalRule::fan ? "{rule=fan}"
                                                         : nullptr;
        if (what)
            fail("lattice", std::string(what) + " is not available with {lattice=rhombic} (uniform meshes with {rule} "
                                                "separating or maxmin only)");
    }
}

}  // namespace

DiagonalRule rule_of(const MeshOptions& o) {
    return o.rule.value_or(o.lattice == LatticeMetric::rhombic ? DiagonalRule::separating : DiagonalRule::fan);
}

void validate(const MeshOptions& options, const GivenOptions& given) {
    check_values(options, given);
    check_contradictions(options, given);
}

const OptionTable<MeshOptions>& mesh2d_option_table() {
    static const OptionTable<MeshOptions> table{entries(), validate};
    return table;
}

}  // namespace warpmesh
