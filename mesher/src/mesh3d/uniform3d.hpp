// uniform3d.hpp — the stages of the 3D mesher (internal; mesh3d.hpp is the
// public side), one a file:
//   lattice3.cpp     the lattice, the window grid and the point numbering
//   signs3.cpp       f and its sign at every point of a window
//   cut_points3.cpp  the cut edges and their exact cut points
//   warp3.cpp        closest-first warping (generic_bcc.hpp's warp_before)
//   stencils3.cpp    the stencil tables (generic_bcc.hpp's stencil_with) and faces
//   face_rule3.cpp   the Delaunay face rule's exact decisions (stage 5's helper)
//   tets3.cpp        background tetrahedra → output tetrahedra, two passes
//   assembly3.cpp    vertices, boundary faces and interfaces, blocks (their
//                    windows) and their merge, mesh_bcc
//   tiling3.cpp      whether blocks tile one lattice exactly once (the merge's check)
//   materials3.cpp   multi-material meshes (mesh_bcc_materials, of the whole lattice
//                    or a block): the points' materials, the junction stencils
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "warpmesh/core/buffer.hpp"
#include "warpmesh/mesh3d/generic_bcc.hpp"
#include "warpmesh/levelset/materials3.hpp"
#include "warpmesh/mesh3d/mesh3d.hpp"

namespace warpmesh::graded3 {
struct Octree3;  // graded/octree3.hpp
}

namespace warpmesh::uniform3d {

// A window of the lattice: the points with doubled coordinates in [lo, hi]
// (lo, hi even: whole cubes), numbered in (z, y, x) order like the lattice.
struct Grid {
    Lattice3 lattice;
    bcc::Ivec lo{0, 0, 0}, hi{0, 0, 0};
    std::int64_t corner_w = 0, corner_h = 0, centre_w = 0, centre_h = 0;
    std::vector<std::int64_t> plane_start;  // per z − lo[2], and the total at the end

    static Grid window(const Lattice3& lattice, const bcc::Ivec& lo, const bcc::Ivec& hi);
    static Grid whole(const Lattice3& lattice);
    std::int64_t count() const { return plane_start.back(); }
    bool contains(const bcc::Ivec& q) const {
        return q[0] >= lo[0] && q[0] <= hi[0] && q[1] >= lo[1] && q[1] <= hi[1] && q[2] >= lo[2] && q[2] <= hi[2];
    }
    // q in the window, a lattice point (all coordinates even or all odd).
    std::int64_t index(const bcc::Ivec& q) const {
        const int z = q[2] - lo[2];
        const std::int64_t s = plane_start[static_cast<std::size_t>(z)];
        if ((q[2] & 1) == 0) return s + ((q[1] - lo[1]) / 2) * corner_w + (q[0] - lo[0]) / 2;
        return s + ((q[1] - lo[1] - 1) / 2) * centre_w + (q[0] - lo[0] - 1) / 2;
    }
    bcc::Ivec point(std::int64_t index) const;
    bcc::Ivec point_in_plane(int z, std::int64_t index) const;  // point(index), index in plane z (no search)
};

}  // namespace warpmesh::uniform3d

namespace warpmesh::uniform3d {

// OpenMP's thread count for one call (0: the default), restored on exit.
struct ThreadCount {
    int saved = 0;
    explicit ThreadCount(int n) {
#ifdef _OPENMP
        saved = omp_get_max_threads();
        if (n > 0) omp_set_num_threads(n);
#else
        (void)n;
#endif
    }
    ~ThreadCount() {
#ifdef _OPENMP
        omp_set_num_threads(saved);
#endif
    }
    ThreadCount(const ThreadCount&) = delete;
    ThreadCount& operator=(const ThreadCount&) = delete;
};

// The forward lattice edges of a point: the 7 directions (of 14) whose far
// endpoint comes later in the (z, y, x) order — +x, +y, +z and the four
// short edges with dz = +1.  A cut point is named by its edge's lower
// endpoint and the edge's slot here.
inline constexpr std::array<int, 7> forward_direction{0, 2, 4, 6, 7, 8, 9};
constexpr int slot_of(int direction) {
    for (int s = 0; s < 7; ++s)
        if (forward_direction[static_cast<std::size_t>(s)] == direction) return s;
    return -1;
}
constexpr bool slot_is_long(int slot) { return slot < 3; }
// The number of slots in a mask of forward slots (7 bits), from a table:
// without -mpopcnt (WARPMESH_POPCNT, off by default) __builtin_popcount is a
// library call, and stage 5 counts a mask per lattice point.
inline int slot_count(unsigned mask) {
    static constexpr std::array<std::uint8_t, 128> table = [] {
        std::array<std::uint8_t, 128> t{};
        for (unsigned m = 1; m < 128; ++m) t[m] = static_cast<std::uint8_t>(t[m >> 1] + (m & 1u));
        return t;
    }();
    return table[mask & 127u];
}

// Whether q is a point of the whole lattice.
inline bool in_lattice(const Lattice3& L, const bcc::Ivec& q) {
    const int odd = q[0] & 1;
    for (std::size_t a = 0; a < 3; ++a) {
        if ((q[a] & 1) != odd) return false;
        if (q[a] < odd || q[a] > 2 * L.cubes[a] - odd) return false;
    }
    return true;
}

// The cubes of layer cz (cube index along z) of a range, in (y, x) order:
// body(m, cx, cy), m the cube's lowest corner in doubled coordinates.
template <class Body>
void for_cubes_in_layer(const CubeRange& r, std::int64_t cz, Body&& body) {
    for (std::int64_t cy = r.lo[1]; cy < r.hi[1]; ++cy)
        for (std::int64_t cx = r.lo[0]; cx < r.hi[0]; ++cx)
            body(bcc::Ivec{static_cast<int>(2 * cx), static_cast<int>(2 * cy), static_cast<int>(2 * cz)}, cx, cy);
}

// The per-point data of a window through the stages.
struct Window {
    Grid grid;
    Buffer<double> value;        // f (signs3; freed after cut_points3)
    Buffer<std::int8_t> sign;    // sign of f; after warp3, the post-warp sign
    Buffer<std::uint8_t> warp;   // after warp3: the warp direction, or bcc::stay
    Buffer<std::uint8_t> cut_mask;   // slots of the forward edges cut before warping
    Buffer<std::uint32_t> cut_first; // index of the point's first cut in cut_u
    std::vector<double> cut_u;       // cut parameter from the lower endpoint
    std::vector<std::pair<std::int64_t, Point3>> warped;  // sorted: warped points and their positions
    // Blocks: points whose warp decision may depend on the world outside the
    // window (warp3's taint).  Empty for the whole lattice.
    std::vector<std::uint8_t> taint;
    std::int64_t warp_count = 0;

    Point3 lattice_position(const bcc::Ivec& q) const { return grid.lattice.position(q); }
    // Cut parameter of the forward edge (p, slot), which must be cut.
    double u(std::int64_t p, int slot) const {
        const unsigned below = cut_mask[static_cast<std::size_t>(p)] & ((1u << slot) - 1);
        return cut_u[cut_first[static_cast<std::size_t>(p)] + static_cast<std::uint32_t>(slot_count(below))];
    }
    // A vertex's position: a lattice point (warped or not) or a cut point.
    Point3 point_position(std::int64_t p) const;
    Point3 cut_position(const bcc::Ivec& lower, int slot, double u) const;
};

// Stages.  Each fills its part of the window; throws InputError for a
// non-finite f (signs3).
void sample_signs(const LevelSet3& f, Window& w);
void find_cuts(const LevelSet3& f, Window& w);
// `blocked`: taint the points that see outside the window (blocks).
void warp_points(const bcc::Alphas& alphas, Window& w, bool blocked);

// The stencil of every (signs, parity) — generic_bcc.hpp's stencil, the
// parity rule — and of every (signs, resolved diagonals) — stencil_with, any
// face rule — with the set of local points it uses (bits 0..3 vertices, 4 + e
// the cut point on local edge e).  A stencil's count and points depend on
// the signs alone (the diagonals only choose how the same polyhedron is
// cut), so stage 5's first pass counts and marks with the parity plans
// whatever the face rule.
struct Plan {
    bcc::Stencil stencil;
    std::uint16_t uses = 0;
    bool quads = false;   // it splits a quad (n- >= 2, n+ >= 1): the face rule decides its diagonals
    bool cyclic = false;  // (diagonal plans) the choice turns an n- = 3 prism's three quads the same way: no stencil
    // face_on[k][f]: the background faces (bit v: the face without local
    // vertex v) that contain face f (the face without vertex f) of output
    // tetrahedron k.
    std::array<std::array<std::uint8_t, 4>, 3> face_on{};
};
// The faces of the lattice's cut-off: (tetrahedron, bit f set for each of its
// faces f lying on a background face with no background tetrahedron behind).
using CutOff = std::pair<std::int64_t, std::uint8_t>;
// code = sum (sign_i + 1) 3^i over the local vertices.
const Plan& plan(int code, int parity);
// All of them: plan(code, parity) is plans()[2 code + parity].
std::span<const Plan> plans();
// By resolved diagonals: diagonal_plans()[diagonal_slots · code +
// diagonal_slot(d)], d's bits face (4) and inside (1).
inline constexpr int diagonal_slots = 32;
constexpr int diagonal_slot(const bcc::Diagonals& d) { return static_cast<int>((d.face & 15u) << 1 | (d.inside ? 1u : 0u)); }
std::span<const Plan> diagonal_plans();

// The Delaunay face rule's choices for a background tetrahedron with
// post-warp signs `sign` and parity bit `parity` (local order): generic_bcc.hpp's
// delaunay_diagonals on the exact cut fractions.  u[e] is the window's cut
// parameter of local edge e (from the edge's lower endpoint; read only on
// (-, +) edges), and bit e of `from_upper` is set when tet_edges[e][0] is the
// upper endpoint (the local fraction is then 1 − u[e]).  The forms' signs
// are exact (face_rule3.cpp), so the two tetrahedra sharing a face agree.
bcc::Diagonals delaunay_choice(const std::array<int, 4>& sign, int parity, const std::array<double, 6>& u, unsigned from_upper);

// The 12 background tetrahedra of a cube m in the local frame, relative to m.
struct TetShape {
    std::array<bcc::Ivec, 4> offset;        // background_tet(0, index)
    int parity = 0;                          // tet_parity (the same for every cube)
    std::array<int, 6> lower{}, slot{};      // per local edge: its lower local vertex, forward slot
    std::array<bcc::Ivec, 4> across{};       // the vertex across face v: x + y − p_v
    // Per local vertex, its slot in the cube's neighbourhood (tets3.cpp): the
    // corner m + 2 (bx, by, bz) is bx + 2 by + 4 bz, the centre m + (1,1,1) is 8,
    // and the centre below it along axis a is 9 + a.
    std::array<int, 4> slot_in_cube{};
};
const std::array<TetShape, 12>& tet_shapes();

// The vertices a stage's tetrahedra use (per window point: used; bit s: its
// cut point s used), and their numbering: per point its id (if used) and the
// id of its first used cut point — lattice points in (z, y, x) order, then
// cut points by (lower endpoint, slot) (mesh3d.hpp, "Vertex numbering").
struct Marks {
    ZeroBuffer<std::uint8_t> point, cut;
};
struct Numbering {
    Buffer<std::int32_t> id, cut_id;
    std::int64_t points = 0, cuts = 0;
};
Numbering number(const Grid& g, const Marks& marks);

// The face opposite local vertex v of a positively oriented tetrahedron,
// oriented outward.
inline constexpr std::array<std::array<int, 3>, 4> outward_face{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};

// Multi-material windows (materials3.cpp): a point's material code — the
// field's material, or outside_code for outside_material — and the cut
// points of the edges whose ends' codes differ, each where the field puts
// the interface (MaterialField3::cut_parameter).  With merge_outside (the
// background is not output), the background and the outside count as one
// material: no cut between them.
inline constexpr std::uint16_t outside_code = 65535;
void find_material_cuts(const MaterialField3& field, std::span<const std::uint16_t> material, bool merge_outside, Window& w);

// The tetrahedra of the cubes [lo, hi) (cube indices) of a warped window.
struct Emitted {
    Buffer<std::array<std::int32_t, 4>> tets;   // window-compact vertex ids
    std::vector<std::uint64_t> tet_key;          // blocks only
    std::vector<CutOff> cut_off;                 // faces on the lattice's cut-off
    Buffer<Point3> vertices;
    std::vector<std::uint8_t> on_level_set;
    std::vector<std::uint64_t> vertex_key;       // blocks only
    std::int64_t all_zero_left_out = 0;          // all-zero background tetrahedra (never output)
    std::int64_t cut_points = 0, warped_vertices = 0;
    // With verify: output background tetrahedra whose key has no claim, and
    // the first one's code; output tetrahedra that fail their own key's
    // claim (key_claim_holds), and the first one's key.
    std::int64_t uncovered_keys = 0;
    std::string first_uncovered;
    std::int64_t key_claim_failures = 0;
    std::string first_key_claim_failure;
    std::int64_t template_tets = 0;  // graded meshes: the templates output (generic_octree.hpp)
};
// Quads split by `rule`; with `verify`, every tetrahedron checked against
// its key's claim (a graded mesh's templates against verify->template_claim,
// where given).  With `tree` (graded meshes, graded/octree3.hpp): the
// finest leaves' background tetrahedra against finest leaves, split by the
// stencils as above, and every leaf's templates (those inside, whole; a
// template with a vertex not strictly on one side throws std::logic_error).
Emitted emit_tets(const Window& w, const CubeRange& range, bool keys, std::uint64_t max_memory, FaceRule rule,
                  const BccKeyClaims* verify = nullptr, const graded3::Octree3* tree = nullptr);

// Whether tetrahedron q satisfies a key's claim with the certificate's own
// test (generic_bcc.hpp, "Angle forms"), in double precision: volume > 0 and
// per edge, with d = n_c·n_d and N = |n_c|²|n_d|²,
//     θ >= θmin  <=>  d <= 0  or  d² <= C_min N,
//     θ <= θmax  <=>  d >= 0  or  d² <= C_max N.
bool key_claim_holds(const std::array<Point3, 4>& q, double cos2_min, double cos2_max);

// A vertex's flag (on_level_set, on_interface): bit 0 (on_flag) the vertex
// is on the level set (an interface); bits 1..6 (domain_face_flags) it is
// also on the domain's face x = xmin, x = xmax, y = ymin, y = ymax, z = zmin,
// z = zmax (LevelSet3::domain, MaterialField3::domain), to within 1e-6
// spacing (a cut point where the hull closes the region is computed to a few
// ulps of its edge).  mark_domain_faces sets those bits on flagged vertices.
inline constexpr std::uint8_t on_flag = 1, domain_face_flags = 0x7e;
void mark_domain_faces(std::span<const Point3> vertices, std::span<std::uint8_t> on, const std::optional<Box3>& domain,
                       double spacing);

// The boundary faces of a mesh whose level-set (or interface) vertices are
// flagged: the faces on the lattice's cut-off, and the unmatched ones of the
// candidate faces with all three vertices flagged, tagged boundary_domain on
// the lattice's cut-off or where the three vertices share a domain face bit
// (the input's domain cut the region off), else boundary_level_set; and its interfaces: the
// matched candidates whose two tetrahedra's regions (mesh.region, set
// before) differ, oriented out of the tetrahedron that comes first.  Both
// lists sorted by their vertex triples.  Throws std::logic_error for a face
// in three tetrahedra.
void find_boundary(TetMesh& mesh, std::span<const std::uint8_t> on_level_set, std::span<const CutOff> cut_off);

// The whole lattice's window (w.grid set) sampled, cut and warped.
void prepare_window(const LevelSet3& f, const BccOptions& o, Window& w);
// The mesh of emitted tetrahedra (boundary faces found) and its counts;
// throws std::logic_error for verify's failures, InputError for an empty
// region.  `seconds` is left 0.
BccMesh finish_mesh(Emitted&& e, const LevelSet3& f, const Lattice3& lattice, const BccOptions& o, std::int64_t warped);

// Throws InputError for alphas not in (0, 1/2) or an unknown face rule.
void check_options(const BccOptions& o);
// Throws InputError unless 0 <= lo <= hi <= lattice.cubes (`what` names the
// caller).
void check_block(const Lattice3& lattice, const CubeRange& block, const std::string& what);
// Blocks: a window around `block` whose decisions on the block's points are
// the whole lattice's.  For halo = 2, 4, 8, ..., `prepare(w)` fills the
// window of the cubes [lo − halo, hi + halo) ∩ the lattice (w.grid, set
// beforehand) — samples, cuts and warps it with warp_points(..., blocked =
// true) — until no tainted point has doubled coordinates in [2 lo − 1, 2 hi]
// (every vertex of the block's background tetrahedra) or the window is the
// whole lattice.
Window block_window(const Lattice3& lattice, const CubeRange& block, const std::function<void(Window&)>& prepare);
// The block `range` of the window's lattice, split by o's face rule and
// alphas, with the given vertices (keys, positions, level-set or interface
// flags) and tetrahedra (keys; lattice_edge from the cut-off faces), one
// region (TetBlock::region empty), and the window's warped points that are
// the block's counted.
TetBlock make_block(const Window& w, const CubeRange& range, const BccOptions& o, std::vector<std::uint64_t>&& vertex_key,
                    std::span<const Point3> vertices, std::vector<std::uint8_t>&& on, std::span<const std::array<std::int32_t, 4>> tets,
                    std::vector<std::uint64_t>&& tet_key, std::span<const CutOff> cut_off);

}  // namespace warpmesh::uniform3d
