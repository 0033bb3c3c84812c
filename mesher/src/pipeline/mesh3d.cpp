// pipeline/mesh3d.cpp — the 3D pipeline (pipeline/mesh3d.hpp): the input's
// level set (or material field), the lattice, the mesher, the
// certification, the measurements, the report.
#include "warpmesh/pipeline/mesh3d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/core/grading.hpp"
#include "warpmesh/mesh3d/graded.hpp"
#include "warpmesh/levelset/image_levelset.hpp"  // parse_label_list
#include "warpmesh/levelset/materials3.hpp"
#include "warpmesh/pipeline/mesh3d_options.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/post/resolution.hpp"
#include "warpmesh/post/tet_checks.hpp"
#include "warpmesh/report/report.hpp"  // json_number

namespace warpmesh {
namespace {

bool is_volume(const Mesh3dInput& input) { return input.index() <= 1; }
bool is_material_shapes(const Mesh3dInput& input) { return std::holds_alternative<MaterialShapes3>(input); }

// The volume-only options given with a shape or a level set.
void check_volume_options(const Mesh3dOptions& o) {
    if (o.labels || o.iso || o.inside_above || o.units || !o.voxel_size.empty() || o.materials)
        throw InputError("labels, iso, inside, units, voxel_size and materials apply to volumes, not to shapes or level sets");
}

// The options of several materials: materials excludes the region options,
// keep_background needs several materials, which take the parity face rule.
void check_material_options(const Mesh3dInput& input, const Mesh3dOptions& o) {
    if (o.materials && (o.labels || o.iso || o.inside_above))
        throw OptionError("materials", "{materials} (every label its own region) excludes labels, iso and inside (one region)");
    if (o.materials && *o.materials != "all") {
        try {
            parse_label_list(*o.materials);
        } catch (const InputError&) {
            throw OptionError("materials", "{materials} expects all or a label list such as 3,41,42 or 1000-1035, got '" +
                                               *o.materials + "'");
        }
    }
    if (!several_materials(input, o)) {
        if (o.keep_background)
            throw OptionError("background", "{background=keep} applies to several materials ({materials}, or material shapes)");
        return;
    }
    if (o.face_rule_in_use(is_material_shapes(input)) != FaceRule::parity)
        throw OptionError("face_rule", "{face_rule=delaunay} is not available with several materials: the two sides of an "
                                       "interface must split their shared quads alike, which the parity rule does "
                                       "({face_rule=parity}, the default there)");
}

// The input's level set (or material field), its default spacing, and the
// input's warnings.
struct Prepared {
    std::unique_ptr<LevelSet3> owned;
    const LevelSet3* f = nullptr;
    std::unique_ptr<MaterialField3> field;  // several materials (then no f)
    double voxel_volume = 0;                // a label volume's voxel (materials: voxel counts)
    std::array<double, 3> voxel{0, 0, 0};   // a label volume's voxel sizes (materials)
    double default_spacing = 0;  // 0: none (shapes, level sets)
    bool large = false;          // a volume of 2^22 voxels or more (progress)
    std::vector<std::string> warnings;
    // A part of a volume (Volume::is_part): its geometry (the options'
    // overrides applied; no values) and its values.
    std::optional<Volume> part;
    const Volume* part_values = nullptr;
};

// A part of a volume (Volume::is_part) is meshed with several materials
// (listed) or as one region in label mode, then given the whole region's
// facts (merge_region_facts); the facts apply to nothing else.
void check_part(const Volume& v, const Mesh3dOptions& o, const LabelRegionFacts* whole) {
    if (whole && (o.materials || !o.labels || !v.is_part()))
        throw InputError("the whole region's facts (region_facts) apply to a part of a volume meshed as one region in label mode (labels)");
    if (v.is_part() && !o.materials && !o.labels)
        throw InputError("a part of a volume is meshed in label mode (labels, with the whole region's facts) or with materials: "
                         "threshold mode's iso and bounds are the whole volume's");
}

// The options' geometry of a volume: voxel_size, units.
bool overrides_geometry(const Mesh3dOptions& o) { return !o.voxel_size.empty() || o.units; }
void apply_geometry(Volume& v, const Mesh3dOptions& o) {
    if (!o.voxel_size.empty()) set_pixel_size(v, o.voxel_size);
    if (o.units == Units::physical && !v.physical)
        throw InputError("units mm: '" + v.source + "' (" + v.format + ") gives no physical voxel size; give one (voxel_size)");
    if (o.units == Units::pixels) {
        v.spacing = {1, 1, 1}, v.origin = {0, 0, 0}, v.axes = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
        v.physical = false;
    }
}

// `owned`: v itself when the pipeline read it (its samples are released as soon as the level set no longer needs them).
void volume_level_set(const Volume& v, const Mesh3dOptions& o, const Mesh3dProgress& progress, Prepared& p, const LabelRegionFacts* whole,
                      Volume* owned = nullptr) {
    check_part(v, o, whole);
    if (v.is_part()) {
        p.part = Volume{};
        p.part->dims = v.dims, p.part->spacing = v.spacing, p.part->origin = v.origin, p.part->axes = v.axes;
        p.part->part_offset = v.part_offset, p.part->whole_dims = v.whole_dims;
    }
    p.default_spacing = v.physical ? std::min({v.spacing[0], v.spacing[1], v.spacing[2]}) : 1.0;
    p.large = v.voxel_count() >= (std::int64_t{1} << 22);
    const std::string size = std::to_string(v.dims[0]) + " x " + std::to_string(v.dims[1]) + " x " + std::to_string(v.dims[2]) + " voxels";
    if (o.materials) {
        if (progress && p.large) progress("materials " + *o.materials + " of " + size);
        p.field = make_volume_materials3(v, *o.materials, o.max_memory);
        p.voxel_volume = v.spacing[0] * v.spacing[1] * v.spacing[2];
        p.voxel = v.spacing;
        return;
    }
    VolumeLevelSet3Options lo;
    lo.max_memory = o.max_memory;
    lo.band = o.band;
    lo.whole = whole;
    if (o.labels) {
        lo.mode = label_options(*o.labels);
    } else {
        lo.mode.iso = o.iso;
        lo.mode.inside_above = o.inside_above.value_or(true);
    }
    if (progress && p.large)
        progress(std::string(o.labels ? "signed distance of the labels" : "threshold level set") + " of " + size);
    p.owned = owned ? make_volume_levelset3(std::move(*owned), lo) : make_volume_levelset3(v, lo);
    p.f = p.owned.get();
    // Neither labels nor iso: threshold mode at a guessed iso, which for a
    // label volume meshes whatever lies above half its largest label.  Say so.
    if (!o.labels && !o.iso)
        p.warnings.push_back("neither labels nor iso given: threshold mode, " + p.f->describe() +
                             "; a label volume needs labels (nonzero, or a list such as 3 or 51,52)");
}

Prepared level_set_of(const Mesh3dInput& input, const Mesh3dOptions& o, const Mesh3dProgress& progress,
                      const LabelRegionFacts* whole = nullptr) {
    validate(input, o);
    if (whole && !std::holds_alternative<std::reference_wrapper<const Volume>>(input))
        throw InputError("the whole region's facts (region_facts) apply to a part of a volume");
    Prepared p;
    std::visit(
        [&](const auto& in) {
            using T = std::decay_t<decltype(in)>;
            if constexpr (std::is_same_v<T, VolumeFile>) {
                Volume v = read_volume(in.path, {o.max_voxels, o.max_memory});
                p.warnings = v.warnings;
                apply_geometry(v, o);
                volume_level_set(v, o, progress, p, whole, &v);
            } else if constexpr (std::is_same_v<T, std::reference_wrapper<const Volume>>) {
                p.warnings = in.get().warnings;
                p.part_values = &in.get();
                if (!overrides_geometry(o)) return volume_level_set(in.get(), o, progress, p, whole);
                Volume v = in.get();  // a copy, to override its geometry
                apply_geometry(v, o);
                volume_level_set(v, o, progress, p, whole);
            } else if constexpr (std::is_same_v<T, Shape3>) {
                p.owned = parse_shape3(in.spec);
                p.f = p.owned.get();
            } else if constexpr (std::is_same_v<T, MaterialShapes3>) {
                p.field = parse_material_shapes3(in.spec);
            } else {
                p.f = &in.get();
            }
        },
        input);
    return p;
}

double spacing_of(const Mesh3dOptions& o, const Prepared& p) { return o.spacing ? *o.spacing : p.default_spacing; }

BccOptions stage_options(const Mesh3dOptions& o, bool material_shapes) {
    BccOptions b;
    b.face_rule = o.face_rule_in_use(material_shapes);
    b.alphas = o.alphas_in_use(material_shapes);
    b.threads = o.threads;
    b.max_memory = o.max_memory;
    return b;
}

// The mesh's volume against the one the input gives its region (a label
// volume's voxels): more than 5 % apart, a warning.  Parts of a region
// thinner than about the spacing (noisy labels, thin sheets) are lost or
// thickened by the lattice, and the mesh looks closed and valid all the same.
void volume_warning(double meshed, double reference, double spacing, std::vector<std::string>& warnings) {
    if (!(reference > 0) || std::abs(meshed - reference) <= 0.05 * reference) return;
    char text[256];
    std::snprintf(text, sizeof text,
                  "the mesh's volume, %.6g, is %.1f %% %s the region's voxels' (%.6g): parts thinner than about the spacing "
                  "%g are %s; a smaller spacing follows the voxels more closely",
                  meshed, 100 * std::abs(meshed - reference) / reference, meshed < reference ? "below" : "above", reference,
                  spacing, meshed < reference ? "lost" : "thickened");
    warnings.emplace_back(text);
}

// The report's counts of the stage's mesh, its non-manifold boundary, and
// its certification by the certificate of `rule` at `alphas`: when it
// applies, every tetrahedron but the junctions' is certified — each from a
// certified key, or an all-zero background tetrahedron output only because
// it meets the claim; the junctions' (several materials) too when
// `junctions`, their certification (proofs/bcc_junctions.cert), applies,
// the bounds then the extremes of both theorems.
Mesh3dReport certified_counts(const BccMesh& m, FaceRule rule, const bcc::Alphas& alphas,
                              const BccCertification& junctions = {}) {
    Mesh3dReport r;
    r.lattice_points = m.lattice_points, r.background_tets = m.background_tets;
    r.cut_points = m.cut_points, r.warped = m.warped, r.all_zero_left_out = m.all_zero_left_out;
    r.seconds = m.seconds;
    r.vertices = static_cast<std::int64_t>(m.mesh.vertices.size());
    r.tets = static_cast<std::int64_t>(m.mesh.tets.size());
    r.boundary_faces = static_cast<std::int64_t>(m.mesh.boundary.size());
    const NonmanifoldBoundary nb = nonmanifold_boundary(m.mesh);
    r.nonmanifold_boundary_edges = nb.edges, r.nonmanifold_boundary_vertices = nb.vertices;
    const BccCertification c = bcc_certification(rule, alphas);
    r.face_rule = rule;
    r.certified = c.certified;
    const bool junctions_certified = m.junction_tets == 0 || junctions.certified;
    r.uncertified_tets = !c.certified ? r.tets : junctions_certified ? 0 : m.junction_tets;
    r.certified_tets = r.tets - r.uncertified_tets;
    r.certified_min_deg = c.min_deg, r.certified_max_deg = c.max_deg;
    if (c.certified && m.junction_tets > 0 && junctions.certified)
        r.certified_min_deg = std::min(c.min_deg, junctions.min_deg), r.certified_max_deg = std::max(c.max_deg, junctions.max_deg);
    r.uncertified_reason = c.uncertified_reason;
    if (c.certified && !junctions_certified)
        r.uncertified_reason = std::to_string(m.junction_tets) + " junction tetrahedra (where three or four materials meet) are "
                               "not certified (" + junctions.uncertified_reason + "); the bounds hold for the other " +
                               std::to_string(r.certified_tets);
    if (!r.uncertified_reason.empty()) r.warnings.push_back(r.uncertified_reason);
    r.verified = c.certified && m.verified;
    return r;
}

// Mesh3dOptions::manifold: the boundary's non-manifold vertices split
// (post/tet_checks.hpp), before the counts; the vertices added.
std::optional<std::int64_t> manifold(const Mesh3dOptions& o, BccMesh& m) {
    if (!o.manifold) return std::nullopt;
    return split_nonmanifold_vertices(m.mesh);
}

// What the report of one region needs of its input besides the mesh (the
// level set's, or merged blocks' BlockFacts).
struct RegionFacts {
    std::optional<double> reference_volume;
    double feature_size = 0, resolution = 0;
};
RegionFacts facts_of(const LevelSet3& f) { return {f.reference_volume(), f.feature_size(), f.resolution()}; }

// The report of one region from the stage's counts, the certification by
// `rule` at `alphas`, the mesh's quality (measured by the caller: none
// without Mesh3dOptions::quality) and the resolution check.
Mesh3dReport region_report(const BccMesh& m, FaceRule rule, const bcc::Alphas& alphas, const std::optional<TetQuality>& quality,
                           const RegionFacts& facts, double spacing) {
    Mesh3dReport r = certified_counts(m, rule, alphas);
    if (quality) {
        r.quality = *quality;
        if (facts.reference_volume) volume_warning(r.quality.volume, *facts.reference_volume, spacing, r.warnings);
    }
    const ResolutionCheck3 res = check_resolution3(m.mesh, facts.feature_size, facts.resolution, spacing);
    r.narrowest_width = res.narrowest_width, r.suggested_spacing = res.suggested_spacing;
    if (res.warning) r.warnings.push_back(*res.warning);
    return r;
}

// Per output material (the background only when kept): its tag, name and,
// for a label volume, its voxels.
std::vector<BlockFacts::Material> material_facts(const MaterialField3& field, double voxel_volume, bool keep_background) {
    std::vector<BlockFacts::Material> out;
    for (int k = keep_background ? 0 : 1; k < field.count(); ++k) {
        BlockFacts::Material x;
        x.tag = field.tag(k), x.name = field.name(k);
        x.reference_volume = field.reference_volume(k);
        if (x.reference_volume && voxel_volume > 0) x.voxels = std::llround(*x.reference_volume / voxel_volume);
        out.push_back(std::move(x));
    }
    return out;
}

// The report of several materials: the counts and certification (the
// junctions' by proofs/bcc_junctions.cert), the quality, per output
// material its tetrahedra and volume (measure_regions3) beside its voxels,
// the interface faces, the junctions, the materials' warnings.
Mesh3dReport materials_report(const BccMesh& m, FaceRule rule, const bcc::Alphas& alphas, bool quality,
                              std::span<const BlockFacts::Material> materials) {
    const BccCertification junctions = bcc_junction_certification(alphas);
    Mesh3dReport r = certified_counts(m, rule, alphas, junctions);
    if (quality) r.quality = measure_quality3(m.mesh);
    Materials3Figures f;
    const std::vector<RegionMeasure> regions = measure_regions3(m.mesh);
    for (const BlockFacts::Material& x : materials) {
        Material3Figures g;
        g.tag = x.tag, g.name = x.name, g.voxels = x.voxels, g.reference_volume = x.reference_volume;
        for (const RegionMeasure& region : regions)
            if (region.tag == g.tag) g.tets = region.tets, g.volume = region.volume;
        f.materials.push_back(std::move(g));
    }
    f.interface_faces = static_cast<std::int64_t>(m.mesh.interfaces.size());
    f.junction_background_tets = m.junction_background_tets, f.junction_tets = m.junction_tets;
    f.all_zero_filled = m.all_zero_filled, f.all_zero_voids = m.all_zero_voids;
    f.junctions_certified = r.certified && junctions.certified;
    for (std::string& w : material_warnings(f)) r.warnings.push_back(std::move(w));
    r.materials = std::move(f);
    return r;
}

// Whether a lattice with a corner on a voxel centre has the voxel
// interfaces (midway between centres) on its planes of points (spaced half
// the spacing apart): iff voxel / spacing is an odd integer along every axis
// (the default spacing, the voxel size, is).  Otherwise such a lattice can
// put them a quarter spacing off its planes, where planar interfaces warp
// whole background tetrahedra flat (left out: voids), and the lattice is
// centred on the field instead.
bool lattice_on_voxel_interfaces(const std::array<double, 3>& voxel, double spacing) {
    for (const double v : voxel) {
        const double k = std::round(v / spacing);
        if (!(v > 0) || std::abs(v / spacing - k) > 1e-9 * k || std::fmod(k, 2.0) != 1) return false;
    }
    return true;
}

// Several materials: the lattice over the field's bounds (a label volume's
// with a corner at its first voxel centre where that puts the voxel
// interfaces on lattice planes: lattice3_for's at_min), the parity face
// rule, the report with the materials' figures and warnings.
// The lattice of several materials: over the field's bounds, for a label
// volume with a corner at its first voxel centre where that puts the voxel
// interfaces on lattice planes (lattice3_for's at_min).  mesh3d, lattice3d
// and mesh3d_block all use it, so that blocks merge into mesh3d's mesh.
Lattice3 material_lattice(const Prepared& p, const Mesh3dOptions& o, double spacing) {
    const bool at_min = o.materials && lattice_on_voxel_interfaces(p.voxel, spacing);
    return lattice3_for(p.field->bounds(), spacing, p.field->describe(), at_min);
}

// The stage's options for several materials: within the parity
// certificate (`certified`), an all-zero background tetrahedron is output
// iff it meets the certificate's claim — the same for a mesh and its blocks.
BccOptions material_stage_options(const Mesh3dInput& input, const Mesh3dOptions& o, bool& certified) {
    BccOptions b = stage_options(o, is_material_shapes(input));
    certified = bcc_certificate_applies(b.alphas, b.face_rule);
    if (const auto c = bcc_claim(b.face_rule); certified && c) b.fill_claim = BccKeyClaim{c->cos2_min, c->cos2_max};
    return b;
}

// Graded meshes (below): the stage's options, the templates' certification
// joined to the report's, the report's figures.
GradedOptions3 graded_options(const Mesh3dOptions& o, double spacing);
void graded_certification(Mesh3dReport& r, std::int64_t template_tets, const BccCertification& t);
Graded3Figures graded_figures(const GradedBccMesh& m, const Mesh3dOptions& o, const GradedOptions3& g, const BccCertification& templates);

// Several materials, uniform or graded (mesh_bcc_materials_graded: the
// interfaces and the outer boundary in the finest band; the bounds the
// uniform multi-material theorem's joined to the templates').
void mesh_materials(const Prepared& p, const Mesh3dInput& input, const Mesh3dOptions& o, double spacing,
                    const Mesh3dProgress& progress, Mesh3dResult& r) {
    r.lattice = material_lattice(p, o, spacing);
    if (progress && (p.large || r.lattice.point_count() >= (std::int64_t{1} << 24)))
        progress("meshing " + std::to_string(p.field->count() - 1) + " materials on a BCC lattice of " +
                 std::to_string(r.lattice.point_count()) + " points at spacing " + json_number(spacing));
    bool certified = false;
    BccOptions b = material_stage_options(input, o, certified);
    // verify checks every two-material side against its key's claim and
    // every junction tetrahedron against its junction key's (bcc_key_claims).
    BccKeyClaims claims = o.verify && certified ? bcc_key_claims(b.face_rule) : BccKeyClaims{};
    const BccCertification templates = o.graded ? bcc_template_certification() : BccCertification{};
    if (o.verify && certified && templates.certified) claims.template_claim = bcc_template_claim();
    if (o.verify && certified) b.verify = &claims;
    const GradedOptions3 g = o.graded ? graded_options(o, spacing) : GradedOptions3{};
    GradedBccMesh m = o.graded ? mesh_bcc_materials_graded(*p.field, r.lattice, b, o.keep_background, g)
                               : GradedBccMesh{mesh_bcc_materials(*p.field, r.lattice, b, o.keep_background), {}, 0};
    const std::optional<std::int64_t> added = manifold(o, m.bcc);
    r.report = materials_report(m.bcc, b.face_rule, b.alphas, o.quality, material_facts(*p.field, p.voxel_volume, o.keep_background));
    r.report.manifold_added_vertices = added;
    if (o.graded) {
        graded_certification(r.report, m.template_tets, templates);
        r.report.graded = graded_figures(m, o, g, templates);
    }
    r.mesh = std::move(m.bcc.mesh);
}


// Blocks of a part of a volume.  Along index axis a, the world axis c it
// runs along (axes[a] = ±e_c), and the cube boundaries of the lattice along
// world axis c: origin_c + n spacing.
std::size_t world_axis(const Volume& g, std::size_t a) {
    for (std::size_t c = 0; c < 3; ++c)
        if (g.axes[a][c] != 0) return c;
    return a;
}
double cube_boundary(const Lattice3& L, std::size_t c, std::int64_t n) {
    const double o = c == 0 ? L.origin.x : c == 1 ? L.origin.y : L.origin.z;
    return o + static_cast<double>(n) * L.spacing;
}

// The whole volume's voxels [lo, hi) (index order i, j, k) that the block
// `range` reads with its window grown by `halo` cubes: the window's box in
// index coordinates (as the material field and the level set map points),
// its voxel cells' corners, `below` and `above` more: several materials,
// the corners' 3 x 3 x 3 neighbourhoods (materials3.hpp's phi), one region
// the voxels their values depend on (label_reach), and one voxel more for
// rounding.
using Index3 = std::array<std::int64_t, 3>;
std::array<Index3, 2> voxels_of_block(const Volume& g, const Lattice3& L, const CubeRange& range, std::int64_t halo,
                                      const Index3& below = {1, 1, 1}, const Index3& above = {1, 1, 1}) {
    const std::array<std::int64_t, 3> n = g.is_part() ? g.whole_dims : g.dims;
    std::array<std::array<std::int64_t, 3>, 2> box{};
    for (std::size_t a = 0; a < 3; ++a) {
        const std::size_t c = world_axis(g, a);
        const double sign = g.axes[a][c] > 0 ? 1 : -1;
        const std::int64_t w0 = std::max<std::int64_t>(0, range.lo[c] - halo), w1 = std::min(L.cubes[c], range.hi[c] + halo);
        const double t0 = sign * (cube_boundary(L, c, w0) - g.origin[c]) / g.spacing[a];
        const double t1 = sign * (cube_boundary(L, c, w1) - g.origin[c]) / g.spacing[a];
        box[0][a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(std::min(t0, t1))) - 1 - below[a], 0, n[a]);
        box[1][a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(std::max(t0, t1))) + 3 + above[a], 0, n[a]);
    }
    return box;
}

// Per output material (the background first when kept), the part's voxels
// whose centres lie in the cubes `range` (half-open along every world axis:
// each voxel of the whole volume is counted by exactly one block).
std::vector<std::int64_t> owned_voxels(const Volume& g, const Volume& values, const MaterialField3& field,
                                       bool keep_background, const Lattice3& L, const CubeRange& range) {
    std::vector<int> material_of(65536, 0);
    for (int m = 1; m < field.count(); ++m) material_of[static_cast<std::size_t>(field.tag(m))] = m;
    std::vector<std::int64_t> count(static_cast<std::size_t>(field.count()), 0);
    std::array<std::size_t, 3> c{};
    for (std::size_t a = 0; a < 3; ++a) c[a] = world_axis(g, a);
    std::array<std::int64_t, 3> i{};
    for (i[2] = 0; i[2] < g.dims[2]; ++i[2])
        for (i[1] = 0; i[1] < g.dims[1]; ++i[1])
            for (i[0] = 0; i[0] < g.dims[0]; ++i[0]) {
                bool own = true;
                for (std::size_t a = 0; a < 3 && own; ++a) {
                    const double x = g.origin[c[a]] + static_cast<double>(g.part_offset[a] + i[a]) * g.spacing[a] * g.axes[a][c[a]];
                    own = cube_boundary(L, c[a], range.lo[c[a]]) <= x && x < cube_boundary(L, c[a], range.hi[c[a]]);
                }
                if (own) ++count[static_cast<std::size_t>(material_of[static_cast<std::size_t>(values.at(i[0], i[1], i[2]))])];
            }
    if (!keep_background) count.erase(count.begin());
    return count;
}

std::string voxel_box_text(const std::array<std::array<std::int64_t, 3>, 2>& b) {
    auto t = [](const std::array<std::int64_t, 3>& x) {
        return "(" + std::to_string(x[0]) + ", " + std::to_string(x[1]) + ", " + std::to_string(x[2]) + ")";
    };
    return "[" + t(b[0]) + ", " + t(b[1]) + ")";
}

// A block of a part whose field or level set read outside it.
InputError part_too_small(const Volume& g) {
    return InputError("the block's part of the volume is too small: the block read voxels outside the part's " +
                      voxel_box_text({g.part_offset,
                                      {g.part_offset[0] + g.dims[0], g.part_offset[1] + g.dims[1], g.part_offset[2] + g.dims[2]}}) +
                      " (i, j, k): its window grew beyond the halo the part was cut for; cut it with twice the halo (block_voxels)");
}

// A block of a part: its materials' voxels are its own cubes'; refused when
// the part lacked voxels the block read.
void part_block_facts(const Prepared& p, const Lattice3& L, const CubeRange& range, bool keep_background, BlockFacts& facts) {
    const Volume& g = *p.part;
    const auto need = voxels_of_block(g, L, range, 0);
    bool covers = !p.field->read_outside_part();
    for (std::size_t a = 0; a < 3; ++a)
        covers = covers && g.part_offset[a] <= need[0][a] && need[1][a] <= g.part_offset[a] + g.dims[a];
    if (!covers) throw part_too_small(g);
    const std::vector<std::int64_t> own = owned_voxels(g, *p.part_values, *p.field, keep_background, L, range);
    for (std::size_t k = 0; k < facts.materials.size(); ++k) facts.materials[k].voxels = own[k], facts.materials[k].reference_volume.reset();
    facts.part = true;
    facts.voxel_volume = p.voxel_volume;
}

// A graded mesh's certification: the stencils' (the report's, from the
// face rule's certificate) and the templates' (proofs/bcc_graded.cert)
// together; without the latter the templates are uncertified.
void graded_certification(Mesh3dReport& r, std::int64_t template_tets, const BccCertification& t) {
    if (!r.certified || template_tets == 0) return;
    if (t.certified) {
        r.certified_min_deg = std::min(r.certified_min_deg, t.min_deg), r.certified_max_deg = std::max(r.certified_max_deg, t.max_deg);
        return;
    }
    r.uncertified_tets += template_tets, r.certified_tets -= template_tets;
    r.uncertified_reason = std::to_string(template_tets) + " template tetrahedra (between octree cells) are not certified (" +
                           t.uncertified_reason + "); the bounds hold for the other " + std::to_string(r.certified_tets);
    r.warnings.push_back(r.uncertified_reason);
    r.verified = false;
}

// A graded mesh of one region (mesh3d/graded.hpp): cells capped by
// max_size, widened by grading; verify checks the stencils' tetrahedra
// against their keys' claims and the templates against theirs.
void mesh_graded(const Prepared& p, const Mesh3dOptions& o, double spacing, Mesh3dResult& r) {
    BccOptions b = stage_options(o, false);
    const bool verify = o.verify && bcc_certificate_applies(b.alphas, b.face_rule);
    const BccCertification templates = bcc_template_certification();
    BccKeyClaims claims = verify ? bcc_key_claims(b.face_rule) : BccKeyClaims{};
    if (verify && templates.certified) claims.template_claim = bcc_template_claim();
    if (verify) b.verify = &claims;
    const GradedOptions3 g = graded_options(o, spacing);
    GradedBccMesh m = mesh_bcc_graded(*p.f, r.lattice, b, g);
    const std::optional<std::int64_t> added = manifold(o, m.bcc);
    r.report = region_report(m.bcc, b.face_rule, b.alphas, o.quality ? std::optional(measure_quality3(m.bcc.mesh, *p.f)) : std::nullopt,
                             facts_of(*p.f), spacing);
    r.report.manifold_added_vertices = added;
    graded_certification(r.report, m.template_tets, templates);
    r.report.graded = graded_figures(m, o, g, templates);
    r.mesh = std::move(m.bcc.mesh);
}

GradedOptions3 graded_options(const Mesh3dOptions& o, double spacing) {
    GradedOptions3 g;
    if (o.max_size) g.max_level = max_level_for_size(*o.max_size, spacing);
    g.buffer = grading_buffer(o.grading);
    return g;
}

Graded3Figures graded_figures(const GradedBccMesh& m, const Mesh3dOptions& o, const GradedOptions3& g, const BccCertification& templates) {
    Graded3Figures f;
    f.leaves_per_level = m.leaves_per_level, f.template_tets = m.template_tets;
    f.max_size = o.max_size.value_or(0), f.max_level = g.max_level;
    f.grading = o.grading, f.grading_buffer = g.buffer;
    f.longest_edge = longest_tet_edge(m.bcc.mesh);
    f.templates_certified = templates.certified, f.template_min_deg = templates.min_deg, f.template_max_deg = templates.max_deg;
    return f;
}

}  // namespace

bool several_materials(const Mesh3dInput& input, const Mesh3dOptions& o) { return o.materials || is_material_shapes(input); }

void validate(const Mesh3dInput& input, const Mesh3dOptions& o) {
    validate(o);  // the table's options (mesh3d_options.hpp)
    if (!o.spacing && !is_volume(input))
        throw InputError("spacing is required for a shape, material shapes or a level set (the lattice's cube side, in its units)");
    if (!is_volume(input)) check_volume_options(o);
    check_material_options(input, o);
    const bcc::Alphas a = o.alphas_in_use(is_material_shapes(input));
    if (!(a.long_den > 0 && a.short_den > 0 && a.long_num > 0 && a.short_num > 0 && 2 * a.long_num < a.long_den &&
          2 * a.short_num < a.short_den))
        throw InputError("the alphas must lie in (0, 1/2)");
    if (o.threads < 0) throw InputError("threads must be 0 (the default) or more");
    if (o.max_voxels < 1) throw InputError("max_voxels must be positive");
    if (o.labels && o.iso) throw InputError("iso (threshold mode) and labels (label mode) exclude each other");
    if (o.labels && o.inside_above) throw InputError("inside applies to threshold mode (iso), not to labels");
    if (o.labels) label_options(*o.labels);  // throws for a bad label list
    if (o.iso && !std::isfinite(*o.iso)) throw InputError("iso must be a finite number");
    if (o.voxel_size.size() > 3) throw InputError("voxel_size takes one to three sizes (x[, y[, z]])");
    for (const double s : o.voxel_size)
        if (!(s > 1e-12 && s < 1e12)) throw InputError("voxel_size: " + std::to_string(s) + " is not a positive size");
}

Mesh3dResult mesh3d(const Mesh3dInput& input, const Mesh3dOptions& o, const Mesh3dProgress& progress) {
    const MemoryCall call;  // max_memory bounds what this call needs (memory.hpp)
    const Prepared p = level_set_of(input, o, progress);
    const double spacing = spacing_of(o, p);
    Mesh3dResult r;
    r.warnings = p.warnings;
    if (o.max_size) check_max_size(*o.max_size, spacing);  // (a volume's default spacing is known now)
    if (p.field) {
        mesh_materials(p, input, o, spacing, progress, r);
        r.warnings.insert(r.warnings.end(), r.report.warnings.begin(), r.report.warnings.end());
        return r;
    }
    r.lattice = lattice3_for(*p.f, spacing);
    if (progress && (p.large || r.lattice.point_count() >= (std::int64_t{1} << 24)))
        progress(std::string(o.graded ? "meshing a graded octree over" : "meshing") + " a BCC lattice of " +
                 std::to_string(r.lattice.point_count()) + " points at spacing " + json_number(spacing));
    if (o.graded) {
        mesh_graded(p, o, spacing, r);
        r.warnings.insert(r.warnings.end(), r.report.warnings.begin(), r.report.warnings.end());
        return r;
    }
    BccOptions b = stage_options(o, false);
    const bool verify = o.verify && bcc_certificate_applies(b.alphas, b.face_rule);
    const BccKeyClaims claims = verify ? bcc_key_claims(b.face_rule) : BccKeyClaims{};
    if (verify) b.verify = &claims;
    BccMesh m = mesh_bcc(*p.f, r.lattice, b);
    const std::optional<std::int64_t> added = manifold(o, m);
    r.report = region_report(m, b.face_rule, b.alphas, o.quality ? std::optional(measure_quality3(m.mesh, *p.f)) : std::nullopt,
                             facts_of(*p.f), spacing);
    r.report.manifold_added_vertices = added;
    r.mesh = std::move(m.mesh);
    r.warnings.insert(r.warnings.end(), r.report.warnings.begin(), r.report.warnings.end());
    return r;
}

namespace {

// Blocks of graded meshes are not built: the octree's leaves span blocks.
void refuse_graded_blocks(const Mesh3dOptions& o) {
    if (o.graded) throw OptionError("graded", "{graded} meshes are not available in blocks (lattice3d, mesh3d_block) yet");
}

}  // namespace

Lattice3 lattice3d(const Mesh3dInput& input, const Mesh3dOptions& o, const LabelRegionFacts* region) {
    const MemoryCall call;
    refuse_graded_blocks(o);
    const Prepared p = level_set_of(input, o, {}, region);
    return p.field ? material_lattice(p, o, spacing_of(o, p)) : lattice3_for(*p.f, spacing_of(o, p));
}

TetBlock mesh3d_block(const Mesh3dInput& input, const Mesh3dOptions& o, const CubeRange& block, const LabelRegionFacts* region) {
    const MemoryCall call;
    if (o.manifold)
        throw OptionError("manifold", "{manifold} applies to whole meshes (mesh3d), not to blocks: their merge keeps "
                                      "the shared vertices");
    refuse_graded_blocks(o);
    const Prepared p = level_set_of(input, o, {}, region);
    const Lattice3 lattice = p.field ? material_lattice(p, o, spacing_of(o, p)) : lattice3_for(*p.f, spacing_of(o, p));
    for (std::size_t a = 0; a < 3; ++a)
        if (block.lo[a] < 0 || block.lo[a] >= block.hi[a] || block.hi[a] > lattice.cubes[a])
            throw InputError("block [lo, hi) must lie in the lattice's cubes (" + std::to_string(lattice.cubes[0]) + ", " +
                             std::to_string(lattice.cubes[1]) + ", " + std::to_string(lattice.cubes[2]) +
                             ") with lo < hi along every axis");
    TetBlock b;
    BlockFacts& facts = b.facts;
    if (!p.field) {
        b = mesh_bcc_block(*p.f, lattice, stage_options(o, false), block);
        if (p.part && p.f->read_outside_part()) throw part_too_small(*p.part);
        facts.source = p.f->describe();
        const RegionFacts region = facts_of(*p.f);
        facts.reference_volume = region.reference_volume;
        facts.feature_size = region.feature_size, facts.resolution = region.resolution;
        facts.open_face_f.reserve(b.open_faces.size());
        for (const auto& face : b.open_faces) {
            std::array<Point3, 3> q;
            for (std::size_t k = 0; k < 3; ++k) q[k] = b.vertices[static_cast<std::size_t>(face[k])];
            facts.open_face_f.push_back(face_fidelity(q, *p.f));
        }
    } else {
        bool certified = false;
        b = mesh_bcc_materials_block(*p.field, lattice, material_stage_options(input, o, certified), o.keep_background, block);
        facts.source = p.field->describe();
        facts.materials = material_facts(*p.field, p.voxel_volume, o.keep_background);
        if (p.part) part_block_facts(p, lattice, block, o.keep_background, facts);
    }
    facts.source += "; band " + std::to_string(o.band) + (o.keep_background ? "; background kept" : "");
    facts.quality = o.quality;
    facts.warnings = p.warnings;
    return b;
}

std::array<std::array<std::int64_t, 3>, 2> block_voxels(const Mesh3dInput& input, const Mesh3dOptions& o, const CubeRange& block,
                                                        std::int64_t halo, const LabelRegionFacts* region) {
    const Prepared p = level_set_of(input, o, {}, region);
    if (!p.part) throw InputError("block_voxels: the input is not a part of a volume (give the whole volume's dimensions)");
    if (halo < 0) throw InputError("block_voxels: the halo must be 0 or more cubes");
    if (p.field) return voxels_of_block(*p.part, material_lattice(p, o, spacing_of(o, p)), block, halo);
    const Index3 reach = label_reach(p.part->spacing, o.band);
    return voxels_of_block(*p.part, lattice3_for(*p.f, spacing_of(o, p)), block, halo, reach, reach);
}

namespace {

// The volume of a part's input, its geometry overridden by the options, for
// the region's facts; InputError unless one region in label mode.
Volume region_part(const Mesh3dInput& input, const Mesh3dOptions& o, const char* what) {
    validate(input, o);
    const auto* v = std::get_if<std::reference_wrapper<const Volume>>(&input);
    if (!v || !o.labels)
        throw InputError(std::string(what) + ": the region's facts are of a volume's part (or the whole volume) in label mode (labels)");
    Volume g = v->get();
    apply_geometry(g, o);
    return g;
}

VolumeLevelSet3Options label_mode(const Mesh3dOptions& o) {
    VolumeLevelSet3Options lo;
    lo.mode = label_options(*o.labels);
    lo.band = o.band, lo.max_memory = o.max_memory;
    return lo;
}

}  // namespace

std::array<std::array<std::int64_t, 3>, 2> region_part_voxels(const Mesh3dInput& input, const Mesh3dOptions& o,
                                                              const std::array<std::array<std::int64_t, 3>, 2>& owned) {
    const Volume g = region_part(input, o, "region_part_voxels");
    const Index3 whole = g.is_part() ? g.whole_dims : g.dims, reach = label_reach(g.spacing, o.band);
    std::array<Index3, 2> box{};
    for (std::size_t a = 0; a < 3; ++a) {
        if (!(owned[0][a] >= 0 && owned[0][a] < owned[1][a] && owned[1][a] <= whole[a]))
            throw InputError("region_part_voxels: the part's own voxels " + voxel_box_text(owned) +
                             " (i, j, k) are not a box of the volume");
        box[0][a] = std::max<std::int64_t>(0, owned[0][a] - reach[a]), box[1][a] = std::min(whole[a], owned[1][a] + reach[a]);
    }
    return box;
}

LabelRegionFacts region_part_facts(const Mesh3dInput& input, const Mesh3dOptions& o,
                                   const std::array<std::array<std::int64_t, 3>, 2>& owned) {
    const MemoryCall call;
    if (const auto* v = std::get_if<std::reference_wrapper<const Volume>>(&input); v && !overrides_geometry(o) && o.labels) {
        validate(input, o);
        return label_part_facts(v->get(), label_mode(o), owned[0], owned[1]);
    }
    return label_part_facts(region_part(input, o, "region_part_facts"), label_mode(o), owned[0], owned[1]);
}

LabelRegionFacts merge_region_facts(std::span<const LabelRegionFacts> parts) { return merge_label_facts(parts, "the volume's parts"); }

namespace {

// Blocks of one mesh carry the same facts (but their own measurements);
// each one-region block one measurement per open face.
void check_block_facts(std::span<const TetBlock> blocks) {
    const BlockFacts& a = blocks.front().facts;
    for (std::size_t i = 0; i < blocks.size(); ++i) {
        const BlockFacts& b = blocks[i].facts;
        const std::string which = "block " + std::to_string(i);
        if (b.source.empty() || b.open_face_f.size() != (b.materials.empty() ? blocks[i].open_faces.size() : 0))
            throw InputError("the blocks do not merge: " + which + " was not made by mesh3d_block (it has no facts of its input)");
        if (b.source != a.source)
            throw InputError("the blocks do not merge: " + which + " and block 0 are of different inputs ('" + b.source + "' and '" +
                             a.source + "')");
        bool same_materials = b.materials.size() == a.materials.size();
        for (std::size_t k = 0; same_materials && k < a.materials.size(); ++k)
            same_materials = b.materials[k].tag == a.materials[k].tag && b.materials[k].name == a.materials[k].name &&
                             (a.part || b.materials[k] == a.materials[k]);
        if (b.quality != a.quality || b.reference_volume != a.reference_volume || b.feature_size != a.feature_size ||
            b.resolution != a.resolution || !same_materials || b.warnings != a.warnings || b.part != a.part ||
            b.voxel_volume != a.voxel_volume)
            throw InputError("the blocks do not merge: " + which + " and block 0 are of different inputs or options");
    }
}

// The materials' figures of merged blocks: of parts, every block's own
// voxels summed.
std::vector<BlockFacts::Material> merged_materials(std::span<const TetBlock> blocks) {
    const BlockFacts& a = blocks.front().facts;
    std::vector<BlockFacts::Material> out = a.materials;
    if (!a.part) return out;
    for (std::size_t k = 0; k < out.size(); ++k) {
        std::int64_t voxels = 0;
        for (const TetBlock& b : blocks) voxels += b.facts.materials[k].voxels.value_or(0);
        out[k].voxels = voxels;
        out[k].reference_volume = static_cast<double>(voxels) * a.voxel_volume;
    }
    return out;
}

// The merged boundary's fidelity to the level set: its level-set faces'
// measurements, each made by the one block that has the face open.
void merged_fidelity(const TetMesh& mesh, std::span<const TetBlock> blocks, TetQuality& q) {
    struct Face {
        std::array<std::uint64_t, 3> key;
        std::array<double, 2> f;
    };
    std::vector<Face> faces;
    std::vector<std::uint64_t> keys;  // the merged vertices' keys, in their order
    for (const TetBlock& b : blocks) {
        keys.insert(keys.end(), b.vertex_key.begin(), b.vertex_key.end());
        for (std::size_t i = 0; i < b.open_faces.size(); ++i) {
            Face x{{}, b.facts.open_face_f[i]};
            for (std::size_t k = 0; k < 3; ++k) x.key[k] = b.vertex_key[static_cast<std::size_t>(b.open_faces[i][k])];
            std::sort(x.key.begin(), x.key.end());
            faces.push_back(x);
        }
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.key < b.key; });
    double fv = 0, fc = 0;
    for (std::size_t i = 0; i < mesh.boundary.size(); ++i) {
        if (mesh.boundary_tag[i] != boundary_level_set) continue;
        std::array<std::uint64_t, 3> key;
        for (std::size_t k = 0; k < 3; ++k) key[k] = keys[static_cast<std::size_t>(mesh.boundary[i][k])];
        std::sort(key.begin(), key.end());
        const auto at = std::lower_bound(faces.begin(), faces.end(), key, [](const Face& a, const auto& k) { return a.key < k; });
        if (at == faces.end() || at->key != key) throw std::logic_error("merge_mesh3d_blocks: a boundary face open in no block");
        fv = std::max(fv, at->f[0]), fc = std::max(fc, at->f[1]);
    }
    q.boundary_vertex_f_max = fv, q.boundary_centroid_f_max = fc;
}

}  // namespace

Mesh3dResult merge_mesh3d_blocks(std::span<const TetBlock> blocks) {
    if (!blocks.empty()) check_block_facts(blocks);
    BccMesh m;
    try {
        m = merge_bcc_blocks(blocks);
    } catch (const std::invalid_argument& e) {
        throw InputError(std::string("the blocks do not merge: ") + e.what());
    }
    const TetBlock& first = blocks.front();
    const BlockFacts& facts = first.facts;
    Mesh3dResult r;
    r.lattice = first.lattice;
    if (!facts.materials.empty()) {
        r.report = materials_report(m, first.face_rule, first.alphas, facts.quality, merged_materials(blocks));
    } else {
        std::optional<TetQuality> quality;
        if (facts.quality) quality = measure_quality3(m.mesh), merged_fidelity(m.mesh, blocks, *quality);
        r.report = region_report(m, first.face_rule, first.alphas, quality, {facts.reference_volume, facts.feature_size, facts.resolution},
                                 first.lattice.spacing);
    }
    r.warnings = facts.warnings;
    r.warnings.insert(r.warnings.end(), r.report.warnings.begin(), r.report.warnings.end());
    r.mesh = std::move(m.mesh);
    return r;
}

void write_block_vtu(const TetBlock& b, const std::string& path, const VtuOptions& options) {
    TetMesh m;
    m.vertices.assign(b.vertices.begin(), b.vertices.end());
    m.tets.assign(b.tets.begin(), b.tets.end());
    m.region.resize(m.tets.size());
    if (b.region.empty()) std::fill(m.region.begin(), m.region.end(), 1);
    else std::copy(b.region.begin(), b.region.end(), m.region.begin());
    m.region_names = b.region_names;
    VtuOptions o = options;
    o.point_global_ids = b.vertex_key, o.cell_global_ids = b.tet_key, o.global_ids = true;
    write_vtu(m, path, o);
}

void check_blocks(std::span<const TetBlock> blocks) {
    if (const auto problem = tiling_problem(blocks)) throw InputError("the blocks do not make one mesh: " + *problem);
    check_block_facts(blocks);
}

std::vector<std::string> write_blocks_pvtu(const std::string& path, std::span<const TetBlock> blocks, const VtuOptions& options) {
    check_blocks(blocks);
    const std::size_t slash = path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
    std::string stem = path.substr(dir.size());
    if (const std::size_t dot = stem.rfind('.'); dot != std::string::npos) stem.resize(dot);
    std::vector<std::string> pieces;
    for (std::size_t i = 0; i < blocks.size(); ++i) {
        char number[16];
        std::snprintf(number, sizeof number, "_%04zu.vtu", i);
        pieces.push_back(stem + number);
        write_block_vtu(blocks[i], dir + pieces.back(), options);
    }
    write_pvtu(path, pieces);
    return pieces;
}

}  // namespace warpmesh
