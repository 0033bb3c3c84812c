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
};

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

void volume_level_set(const Volume& v, const Mesh3dOptions& o, const Mesh3dProgress& progress, Prepared& p) {
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
    if (o.labels) {
        lo.mode = label_options(*o.labels);
    } else {
        lo.mode.iso = o.iso;
        lo.mode.inside_above = o.inside_above.value_or(true);
    }
    if (progress && p.large)
        progress(std::string(o.labels ? "signed distance of the labels" : "threshold level set") + " of " + size);
    p.owned = make_volume_levelset3(v, lo);
    p.f = p.owned.get();
    // Neither labels nor iso: threshold mode at a guessed iso, which for a
    // label volume meshes whatever lies above half its largest label.  Say so.
    if (!o.labels && !o.iso)
        p.warnings.push_back("neither labels nor iso given: threshold mode, " + p.f->describe() +
                             "; a label volume needs labels (nonzero, or a list such as 3 or 51,52)");
}

Prepared level_set_of(const Mesh3dInput& input, const Mesh3dOptions& o, const Mesh3dProgress& progress) {
    validate(input, o);
    Prepared p;
    std::visit(
        [&](const auto& in) {
            using T = std::decay_t<decltype(in)>;
            if constexpr (std::is_same_v<T, VolumeFile>) {
                Volume v = read_volume(in.path, {o.max_voxels, o.max_memory});
                p.warnings = v.warnings;
                apply_geometry(v, o);
                volume_level_set(v, o, progress, p);
            } else if constexpr (std::is_same_v<T, std::reference_wrapper<const Volume>>) {
                p.warnings = in.get().warnings;
                if (!overrides_geometry(o)) return volume_level_set(in.get(), o, progress, p);
                Volume v = in.get();  // a copy, to override its geometry
                apply_geometry(v, o);
                volume_level_set(v, o, progress, p);
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

// The report of one region from the stage's counts, the certification and the measurements.
Mesh3dReport report_of(const BccMesh& m, const LevelSet3& f, const Mesh3dOptions& o, double spacing) {
    Mesh3dReport r = certified_counts(m, o.face_rule_in_use(), o.alphas_in_use());
    if (o.quality) r.quality = measure_quality3(m.mesh, f);
    if (o.quality)
        if (const auto ref = f.reference_volume()) volume_warning(r.quality.volume, *ref, spacing, r.warnings);
    const ResolutionCheck3 res = check_resolution3(m.mesh, f, spacing);
    r.narrowest_width = res.narrowest_width, r.suggested_spacing = res.suggested_spacing;
    if (res.warning) r.warnings.push_back(*res.warning);
    return r;
}

// Per output material: its tetrahedra and volume (measure_regions3), its
// voxels and their volume; the interface faces; the junctions.
Materials3Figures material_figures(const BccMesh& m, const MaterialField3& field, double voxel_volume, bool keep_background) {
    Materials3Figures f;
    const std::vector<RegionMeasure> regions = measure_regions3(m.mesh);
    for (int k = keep_background ? 0 : 1; k < field.count(); ++k) {
        Material3Figures x;
        x.tag = field.tag(k), x.name = field.name(k);
        for (const RegionMeasure& g : regions)
            if (g.tag == x.tag) x.tets = g.tets, x.volume = g.volume;
        x.reference_volume = field.reference_volume(k);
        if (x.reference_volume && voxel_volume > 0) x.voxels = std::llround(*x.reference_volume / voxel_volume);
        f.materials.push_back(std::move(x));
    }
    f.interface_faces = static_cast<std::int64_t>(m.mesh.interfaces.size());
    f.junction_background_tets = m.junction_background_tets, f.junction_tets = m.junction_tets;
    f.all_zero_filled = m.all_zero_filled, f.all_zero_voids = m.all_zero_voids;
    return f;
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
    const BccKeyClaims claims = o.verify && certified ? bcc_key_claims(b.face_rule) : BccKeyClaims{};
    if (o.verify && certified) b.verify = &claims;
    BccMesh m = mesh_bcc_materials(*p.field, r.lattice, b, o.keep_background);
    const std::optional<std::int64_t> added = manifold(o, m);
    const BccCertification junctions = bcc_junction_certification(b.alphas);
    r.report = certified_counts(m, b.face_rule, b.alphas, junctions);
    r.report.manifold_added_vertices = added;
    if (o.quality) r.report.quality = measure_quality3(m.mesh);
    r.report.materials = material_figures(m, *p.field, p.voxel_volume, o.keep_background);
    r.report.materials->junctions_certified = r.report.certified && junctions.certified;
    for (std::string& w : material_warnings(*r.report.materials)) r.report.warnings.push_back(std::move(w));
    r.mesh = std::move(m.mesh);
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
    if (p.field) {
        mesh_materials(p, input, o, spacing, progress, r);
        r.warnings.insert(r.warnings.end(), r.report.warnings.begin(), r.report.warnings.end());
        return r;
    }
    r.lattice = lattice3_for(*p.f, spacing);
    if (progress && (p.large || r.lattice.point_count() >= (std::int64_t{1} << 24)))
        progress("meshing a BCC lattice of " + std::to_string(r.lattice.point_count()) + " points at spacing " + json_number(spacing));
    BccOptions b = stage_options(o, false);
    const bool verify = o.verify && bcc_certificate_applies(b.alphas, b.face_rule);
    const BccKeyClaims claims = verify ? bcc_key_claims(b.face_rule) : BccKeyClaims{};
    if (verify) b.verify = &claims;
    BccMesh m = mesh_bcc(*p.f, r.lattice, b);
    const std::optional<std::int64_t> added = manifold(o, m);
    r.report = report_of(m, *p.f, o, spacing);
    r.report.manifold_added_vertices = added;
    r.mesh = std::move(m.mesh);
    r.warnings.insert(r.warnings.end(), r.report.warnings.begin(), r.report.warnings.end());
    return r;
}

Lattice3 lattice3d(const Mesh3dInput& input, const Mesh3dOptions& o) {
    const MemoryCall call;
    const Prepared p = level_set_of(input, o, {});
    return p.field ? material_lattice(p, o, spacing_of(o, p)) : lattice3_for(*p.f, spacing_of(o, p));
}

TetBlock mesh3d_block(const Mesh3dInput& input, const Mesh3dOptions& o, const CubeRange& block) {
    const MemoryCall call;
    if (o.manifold)
        throw OptionError("manifold", "{manifold} applies to whole meshes (mesh3d), not to blocks: their merge keeps "
                                      "the shared vertices");
    const Prepared p = level_set_of(input, o, {});
    const Lattice3 lattice = p.field ? material_lattice(p, o, spacing_of(o, p)) : lattice3_for(*p.f, spacing_of(o, p));
    for (std::size_t a = 0; a < 3; ++a)
        if (block.lo[a] < 0 || block.lo[a] >= block.hi[a] || block.hi[a] > lattice.cubes[a])
            throw InputError("block [lo, hi) must lie in the lattice's cubes (" + std::to_string(lattice.cubes[0]) + ", " +
                             std::to_string(lattice.cubes[1]) + ", " + std::to_string(lattice.cubes[2]) +
                             ") with lo < hi along every axis");
    if (!p.field) return mesh_bcc_block(*p.f, lattice, stage_options(o, false), block);
    bool certified = false;
    return mesh_bcc_materials_block(*p.field, lattice, material_stage_options(input, o, certified), o.keep_background, block);
}

Mesh3dResult merge_mesh3d_blocks(std::span<const TetBlock> blocks) {
    Mesh3dResult r;
    try {
        r.mesh = merge_tet_blocks(blocks);
    } catch (const std::invalid_argument& e) {
        throw InputError(std::string("the blocks do not merge: ") + e.what());
    }
    r.report.vertices = static_cast<std::int64_t>(r.mesh.vertices.size());
    r.report.tets = static_cast<std::int64_t>(r.mesh.tets.size());
    r.report.boundary_faces = static_cast<std::int64_t>(r.mesh.boundary.size());
    return r;
}

}  // namespace warpmesh
