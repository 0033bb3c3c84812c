// mesh3d.hpp — the 3D mesher: a level set f(x, y, z) in, a conforming
// tetrahedral mesh of {f <= 0} out, by lattice warping on the BCC lattice
// (isosurface stuffing), every stage from the one definition the 3D proof is
// about (generic_bcc.hpp).
//
//   auto f = warpmesh::parse_shape3("sphere:0,0,0,1");
//   warpmesh::Mesh3dOptions o;
//   o.spacing = 0.1;
//   warpmesh::Mesh3dReport report;
//   warpmesh::TetMesh m = warpmesh::mesh3d(*f, o, &report);
//
// Volumes: read_volume (volume.hpp), then make_volume_levelset3 (below)
// gives the level set, in millimetres for physical volumes.
//
// THE OUTPUT (tet_mesh.hpp's invariants, checked by check_tet_mesh):
// positively oriented tetrahedra, each interior face shared by exactly two,
// the boundary faces oriented outward and tagged boundary_level_set (all
// three vertices on the level set) or boundary_domain (the region is cut off
// by the lattice: only for level sets whose bounds() do not enclose the
// region, or volumes whose region reaches the lattice's edge).  One region,
// tag 1.
//
// VERTEX NUMBERING (what makes blocks mergeable and the output independent
// of the thread count).  Lattice points come first, in lexicographic order of
// their doubled coordinates read (z, y, x) — z slowest; then the cut points,
// ordered by their edge's lower endpoint (the endpoint that comes first in
// that order) and then by the edge's direction index (neighbour_offsets).
// Only used vertices are kept, in that order.  Tetrahedra come in the order
// of their background tetrahedron's owning cube (z, y, x), its index 0..11
// (background_tet), then the stencil's order.  The boundary faces are sorted
// by their vertex triples.  `vertex_key` (below) is the global name of a
// vertex in this order.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "warpmesh/certify/bcc_certified.hpp"  // FaceRule
#include "warpmesh/mesh3d/generic_bcc.hpp"
#include "warpmesh/levelset/image_levelset.hpp"  // ImageLevelSetOptions: the volume modes
#include "warpmesh/core/memory.hpp"
#include "warpmesh/core/tet_mesh.hpp"

namespace warpmesh {

struct Volume;  // volume.hpp

struct Box3 {
    double xmin, ymin, zmin, xmax, ymax, zmax;
};

// ---------------------------------------------------------------------------
// Level sets in 3D.  f < 0 inside, f > 0 outside, f = 0 on the boundary.
class LevelSet3 {
public:
    virtual ~LevelSet3() = default;
    // f at a point; finite wherever the mesher asks.
    virtual double value(double x, double y, double z) const = 0;
    // A box containing the region {f <= 0} (volumes: the volume's extent).
    // The lattice covers it with a margin (lattice3_for).
    virtual Box3 bounds() const = 0;
    // The parameter u in (0, 1) of a zero of f on a + u (b − a), given f(a) =
    // fa and f(b) = fb of strictly opposite signs.  Default: bracketed_root3.
    virtual double cut_parameter(Point3 a, Point3 b, double fa, double fb) const;
    // The thinnest feature of the region (a sphere's radius, a torus's tube
    // radius, half a box's smallest side; volumes: the largest inscribed
    // distance of the region — for a label volume only while it is within
    // the distance band, else 0), for the coarse-spacing warning; 0: unknown.
    virtual double feature_size() const { return 0; }
    // The input's own resolution (volumes: the smallest voxel spacing; 0 for
    // analytic level sets): the coarse-spacing warning never suggests a
    // spacing below it and is silent at a spacing at or below it.
    virtual double resolution() const { return 0; }
    // Exact volume of {f <= 0} where known (analytic shapes), for tests.
    virtual std::optional<double> exact_volume() const { return std::nullopt; }
    virtual std::string describe() const = 0;
};

// Illinois regula falsi with a bisection step every eighth iteration, to
// convergence (the bracket shrinks to a few ulps or f = 0 is hit), keeping a
// strict sign bracket: the result lies in (0, 1).  The same root finder as
// 2D's bracketed_root (one implementation, src/core/root_finder.hpp).
double bracketed_root3(const LevelSet3& f, Point3 a, Point3 b, double fa, double fb);

// A level set from any callable (tests, Python): f and a box around the region.
class FunctionLevelSet3 final : public LevelSet3 {
public:
    FunctionLevelSet3(std::function<double(double, double, double)> f, Box3 box, std::string name = "function");
    double value(double x, double y, double z) const override { return f_(x, y, z); }
    Box3 bounds() const override { return box_; }
    std::string describe() const override { return name_; }

private:
    std::function<double(double, double, double)> f_;
    Box3 box_;
    std::string name_;
};

// Analytic shapes, the 3D siblings of shapes.hpp, with the same syntax:
//   sphere:cx,cy,cz,r            f = |p − c| − r
//   ellipsoid:cx,cy,cz,a,b,c     f = min(a,b,c) (|((x−cx)/a, (y−cy)/b, (z−cz)/c)| − 1)
//   torus:cx,cy,cz,R,r           axis z: f = |(ρ − R, z − cz)| − r, ρ = |(x−cx, y−cy)|, 0 < r < R
//   box:x0,y0,z0,x1,y1,z1        f = max(x0 − x, x − x1, y0 − y, ...)
//   cylinder:x0,y0,z0,x1,y1,z1,r the capped cylinder of radius r around the
//                                segment p0 p1: f = max(dist to the axis − r,
//                                |t − L/2| − L/2), t the position along the axis
//   union(S;S[;S...])  intersect(S;S[;S...])  diff(S;S[;S...])  (nestable)
// union = min, intersection = max, difference = max(f1, −f2).  Throws
// InputError naming the string and the problem (an unknown shape, a wrong
// number of parameters, a non-positive radius or size, an intersection of
// shapes whose boxes are disjoint: the region is empty).
std::unique_ptr<LevelSet3> parse_shape3(const std::string& spec);

// The level set of a volume (volume.hpp's geometry: physical coordinates in
// mm, or voxel indices for a non-physical volume), in the modes of 2D images
// (ImageLevelSetOptions; its `geometry` is ignored, the volume has its own):
//   threshold  f = iso − G (inside_above, the default) or G − iso, G the
//              trilinear interpolant of the voxel values; iso defaults to the
//              middle of the value range;
//   label      the region is the voxels whose value is in `labels` (or every
//              non-zero voxel with label_nonzero); f is the signed distance
//              between voxel centres, d_out − h/2 outside and −(d_in − h/2)
//              inside (d the exact Euclidean distance, spacing-weighted, to the
//              nearest voxel centre of the other class; h/2 puts the boundary
//              midway between a voxel inside and its 6-neighbour outside along
//              each axis), interpolated trilinearly.  It is computed exactly
//              only in a band of `band` voxels around the boundary (farther, f
//              is clamped to ±band × the largest spacing: the sign is all the
//              mesher needs there), on the region's bounding box plus that
//              band, as 4-byte floats.
// The region is cut off at the hull of the voxel centres (f = max(the
// interpolant at the nearest point of the hull, the box distance to the hull
// in f's units): continuous, and a region reaching the volume's edge is
// closed there by boundary faces on the level set).  Memory: refused (InputError naming --max-memory) before anything is
// allocated when the field would take the resident memory above max_memory.
// Throws InputError for label mode on non-integer values, labels absent from
// the volume (an empty region), a volume less than 2 voxels along an axis.
struct VolumeLevelSet3Options {
    ImageLevelSetOptions mode;  // threshold / label, iso, inside_above, labels, label_nonzero
    int band = 4;               // voxels of exact distance around the boundary (label mode), >= 2
    std::uint64_t max_memory = default_max_memory;
};
std::unique_ptr<LevelSet3> make_volume_levelset3(const Volume& volume, const VolumeLevelSet3Options& options);

// ---------------------------------------------------------------------------
// The lattice.  Cubes [0, cubes[a]) along each axis of side `spacing`; the
// point with doubled coordinates q is at origin + q · spacing / 2; corners
// have 0 <= q <= 2 cubes, centres 1 <= q <= 2 cubes − 1.  A background
// tetrahedron exists iff both cubes of its face exist, so the covered region
// is the box less a layer of up to one cube at its faces; lattice3_for puts
// two cubes of margin around bounds().
struct Lattice3 {
    double spacing = 1;
    Point3 origin{0, 0, 0};
    std::array<std::int64_t, 3> cubes{0, 0, 0};
    Point3 position(const bcc::Ivec& q) const {
        const double h = 0.5 * spacing;
        return {origin.x + q[0] * h, origin.y + q[1] * h, origin.z + q[2] * h};
    }
    // Lattice points (corners and centres).
    std::int64_t point_count() const;
    // The global index of lattice point q in the (z, y, x) order.
    std::int64_t point_index(const bcc::Ivec& q) const;
};
// The lattice of `spacing` over f.bounds() with two cubes of margin.  Throws
// InputError for a spacing that is not positive and finite, or a lattice of
// more than 2^31 points or cubes (name: --spacing).
Lattice3 lattice3_for(const LevelSet3& f, double spacing);

// ---------------------------------------------------------------------------
// Options and report.
//
// The face rule (generic_bcc.hpp, "The diagonal choices") splits the quads of
// the stencils: `parity` (Labelle–Shewchuk's parity rule, proofs/bcc.cert) or
// `delaunay` (each face quad by the empty-circle test, the prism's inside
// quad by the shorter diagonal; proofs/README.md, "The Delaunay face rule"),
// decided by exact signs of the rule's forms so that the two tetrahedra
// sharing a face agree.  Each rule has its own alphas, those its certificate
// is proved at (face_rule_alphas).  The default is the Delaunay face rule:
// its certificate's bounds, [11.78°, 161.25°], are tighter at both ends than
// the parity rule's [10.76°, 164.75°]; the default alphas follow the rule.
inline constexpr FaceRule default_face_rule = FaceRule::delaunay;
constexpr bcc::Alphas face_rule_alphas(FaceRule rule) {
    return rule == FaceRule::delaunay ? bcc::delaunay_alphas : bcc::parity_alphas;
}

struct Mesh3dOptions {
    double spacing = 1;                             // lattice spacing s (cube side), the level set's units
    FaceRule face_rule = default_face_rule;         // how the stencils' quads are split (above)
    // Violation thresholds (α_long, α_short); none: face_rule_alphas(face_rule).
    std::optional<bcc::Alphas> alphas;
    int threads = 0;                                // OpenMP threads; 0 = the OpenMP default
    std::uint64_t max_memory = default_max_memory;  // refuse (InputError naming --max-memory) above it
    // Check every tetrahedron, once, against its own background
    // tetrahedron's key claim in the face rule's certificate (compiled in;
    // each key's claim is within the theorem); a key the certificate does
    // not list or a violation throws std::logic_error (an internal failure,
    // not bad input).  Only with the certificate's alphas.
    bool verify = false;
    // Measure dihedral angles, radius ratios and the boundary's distance to
    // the level set for the report (a second pass over the mesh).
    bool quality = true;
    // The alphas in use.
    bcc::Alphas alphas_in_use() const { return alphas ? *alphas : face_rule_alphas(face_rule); }
};

struct Mesh3dReport {
    // Counts.
    std::int64_t lattice_points = 0, background_tets = 0;  // in the lattice
    std::int64_t cut_points = 0;    // cut points kept (vertices)
    std::int64_t warped = 0;        // lattice points warped onto the level set
    std::int64_t vertices = 0, tets = 0, boundary_faces = 0;
    // All-zero background tetrahedra (four vertices on the level set): never
    // output (proofs/README.md, step 6), counted here; their volume, within
    // the α-band of the surface, is not in the mesh.
    std::int64_t all_zero_left_out = 0;
    double volume = 0;               // sum of the tetrahedra's volumes
    // Measured quality (Mesh3dOptions::quality).
    double min_dihedral_deg = 0, max_dihedral_deg = 0;
    static constexpr int radius_ratio_bins = 10;  // bin i: [i/10, (i+1)/10), 1 in the last
    std::array<std::int64_t, radius_ratio_bins> radius_ratio_histogram{};
    double radius_ratio_min = 0, radius_ratio_mean = 0;  // 3 r_in / R_circ (1: regular)
    // Boundary fidelity: max |f| at the boundary vertices (0 up to the root
    // finder's tolerance) and at the boundary faces' centroids (the surface's
    // deviation between its vertices; a distance for signed-distance level
    // sets), in the level set's units.
    double boundary_vertex_f_max = 0, boundary_centroid_f_max = 0;
    // The boundary's non-manifold edges and vertices (nonmanifold_boundary).
    std::int64_t nonmanifold_boundary_edges = 0, nonmanifold_boundary_vertices = 0;
    // Certification by the face rule's certificate (bcc_certificate_path):
    // certified: it is compiled in and its alphas are the options'; the
    // bounds then hold for every tetrahedron (each comes from a certified
    // key: uncertified is 0), else every tetrahedron is uncertified and a
    // warning says why.  verified: every tetrahedron was checked against its
    // own key's claim (Mesh3dOptions::verify).
    FaceRule face_rule = FaceRule::parity;  // the rule the mesh was split by
    bool certified = false;
    double certified_min_deg = 0, certified_max_deg = 0;
    std::int64_t certified_tets = 0, uncertified_tets = 0;
    std::string uncertified_reason;  // why not certified (also a warning); empty when certified
    bool verified = false;
    // The resolution check: the narrowest closed boundary component's width
    // 6V/A (a sphere's diameter), and a spacing resolving it (0: resolved).
    double narrowest_width = 0, suggested_spacing = 0;
    std::vector<std::string> warnings;  // e.g. the spacing is too coarse
    double seconds = 0;                 // meshing time (without the quality pass)
};

// Mesh {f <= 0}.  Throws InputError for bad options (spacing not positive and
// finite, alphas not in (0, 1/2)), a lattice or a mesh over max_memory (before
// allocating it), an empty region ("no tetrahedron inside at spacing s").
// A spacing too coarse for the input gives a warning in the report naming a
// spacing that resolves it.
TetMesh mesh3d(const LevelSet3& f, const Mesh3dOptions& options, Mesh3dReport* report = nullptr);

// ---------------------------------------------------------------------------
// Blocks (issue 30's "beyond one machine").  The cubes [lo, hi) of the
// lattice `lattice` are meshed on their own, looking at the level set on the
// block grown by a halo large enough for the closest-first warping order to
// be decided there exactly (the halo grows until no decision in the block
// depends on the halo's edge); vertices carry their global key (the order
// above: lattice point index, then point_count() + 7 × lower endpoint's
// index + the edge's slot among the 7 forward directions).  merge_tet_blocks
// of blocks that tile the lattice's cubes equals mesh3d(f, options) on that
// lattice exactly: vertices, tetrahedra, boundary and tags.
struct CubeRange {
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{0, 0, 0};
};
struct TetBlock {
    std::vector<std::uint64_t> vertex_key;        // sorted, one per vertex
    std::vector<Point3> vertices;
    std::vector<std::uint8_t> on_level_set;       // per vertex: zero lattice point or cut point
    std::vector<std::array<std::int32_t, 4>> tets;  // indices into vertices
    std::vector<std::uint64_t> tet_key;           // sorted: the tetrahedra's global order
    std::vector<std::uint8_t> lattice_edge;       // per tet: bit f set if its face without vertex f is on the lattice's cut-off
};
TetBlock mesh3d_block(const LevelSet3& f, const Mesh3dOptions& options, const Lattice3& lattice,
                      const CubeRange& block);
// Merge blocks tiling the lattice (any order): vertices by key, tetrahedra by
// key, boundary faces found as in mesh3d.  Throws std::invalid_argument if
// two blocks give the same key different positions or a tetrahedron twice.
TetMesh merge_tet_blocks(std::span<const TetBlock> blocks);
// mesh3d on a given lattice (its spacing wins over options.spacing).
TetMesh mesh3d_on(const LevelSet3& f, const Mesh3dOptions& options, const Lattice3& lattice,
                  Mesh3dReport* report = nullptr);

// ---------------------------------------------------------------------------
// Checks and quality of any tetrahedral mesh.
struct TetMeshCheck {
    bool ok = true;
    std::vector<std::string> problems;  // the first few, each naming the element
    std::int64_t inverted = 0;          // tetrahedra with det <= 0
    std::int64_t nonmanifold_faces = 0; // faces in more than two tetrahedra
    std::int64_t boundary_mismatch = 0; // boundary faces missing, extra or not outward
    std::int64_t unused_vertices = 0;
    // Not problems (ok stays true): the boundary's non-manifold places
    // (nonmanifold_boundary below), counted.
    std::int64_t nonmanifold_boundary_edges = 0, nonmanifold_boundary_vertices = 0;
};
// From scratch: positive orientation, every face in one or two tetrahedra,
// the one-tetrahedron faces exactly the boundary list, each oriented as its
// tetrahedron sees it from outside, every vertex used, tags per face; and the
// boundary's non-manifold edges and vertices, counted.
TetMeshCheck check_tet_mesh(const TetMesh& mesh);

// The boundary surface's non-manifold places.  A conforming mesh with a
// closed, outward boundary can still have boundary edges in more than two
// boundary triangles (four, six, ...: two parts of the region touch along
// the edge) and boundary vertices around which the boundary triangles are
// not one disc (their link, the edges opposite the vertex, is not one
// cycle: two parts touch at the vertex, or it ends a non-manifold edge).
// mesh3d's can, where all-zero background tetrahedra are left out
// (docs/3d.md, "Non-manifold boundary").
struct NonmanifoldBoundary {
    std::int64_t edges = 0, vertices = 0;
};
NonmanifoldBoundary nonmanifold_boundary(const TetMesh& mesh);

// The six dihedral angles (degrees) of a tetrahedron, at edges 01 02 03 12
// 13 23, and its radius ratio 3 r_in / R_circ (1 for the regular one, 0 flat).
std::array<double, 6> dihedral_angles_deg(const std::array<Point3, 4>& p);
double radius_ratio(const std::array<Point3, 4>& p);

// Fill the report's quality fields (dihedral extremes, radius-ratio
// histogram, boundary fidelity against f, volume) from a mesh.
void measure_quality3(const TetMesh& mesh, const LevelSet3& f, Mesh3dReport& report);

// The claim of a face rule's certificate (bcc_certificate_path, compiled in):
// its alphas and the dihedral bounds, or nullopt when the build has none.
struct BccClaim {
    bcc::Alphas alphas;
    double min_deg, max_deg;
    // cos² thresholds as the certificate states them (dyadic rationals).
    double cos2_min, cos2_max;
};
std::optional<BccClaim> bcc_claim(FaceRule rule = FaceRule::parity);

}  // namespace warpmesh
