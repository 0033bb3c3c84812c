// tets3.cpp — stage 5: every background tetrahedron of the cubes of a range
// split by its stencil (step 6 of generic_bcc.hpp's contract), in two passes
// over the cube layers (z) so that the output is written in place, in the
// same order for any number of threads:
//   A. count each layer's tetrahedra and mark the lattice points and the cut
//      points they use (neighbouring layers share points: relaxed atomic
//      stores and, for the surface-sized cut marks, atomic or);
//   B. number the used vertices in (z, y, x) order — lattice points, then
//      cut points by (lower endpoint, slot) — and write the tetrahedra.
// A background tetrahedron of cube m with index i (background_tet) exists iff
// the cube below m along axis i / 4 exists (its centre c1).  An all-zero one
// (four zero vertices) is never output, only counted.  A cube whose 12
// tetrahedra exist and whose 12 points (8 corners, its centre, the centres
// below it) are all inside outputs its 12 background tetrahedra whole: the
// common case, taken without the stencil; one whose 12 points are all
// outside (+) has nothing to output or count, and is skipped.
// The quads (background tetrahedra with n- >= 2, n+ >= 1) are split by the
// face rule: parity from the (signs, parity) table, the Delaunay face rule
// from the (signs, diagonals) table after delaunay_choice (face_rule3.cpp)
// decides the diagonals exactly from the cut parameters.  A stencil's count
// and points do not depend on its diagonals, so pass A is the same for both.
// With verify every output tetrahedron is checked against its own
// background tetrahedron's key claim (BccKeyClaims: the face rule's
// certificate's, given by the pipeline) as it is written (the whole ones
// against the claim of the all-− key, looked up once).
#include <atomic>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "uniform3d.hpp"
#include "mesh3d/graded/octree3.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"  // key_of, code_of
#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/memory.hpp"

namespace warpmesh::uniform3d {
namespace {

// The 12 points around cube m (TetShape::slot_in_cube) and their signs.
struct Neighbourhood {
    std::array<std::int64_t, 12> at{};
    std::array<int, 12> sign{};
    bool all_inside = false;   // every tetrahedron exists and every sign is −
    bool all_outside = false;  // every sign is + (no tetrahedron has a − or an all-zero vertex set: nothing to output or count)
};

struct Layout {
    const Window& w;
    const FaceRule rule;
    const graded3::Octree3* tree = nullptr;  // graded meshes
    const std::array<TetShape, 12>& shapes = tet_shapes();
    std::span<const Plan> plans = uniform3d::plans();  // looked up once, not per tetrahedron
    std::span<const Plan> by_diagonals = uniform3d::diagonal_plans();
    std::int64_t plane_pair = 0;  // index step of 2 along z
    // The neighbourhood slots a cube's 12 tetrahedra use: the corners on its
    // three lower faces and the 4 centres, not the corner m + (2, 2, 2) (the
    // cubes above use that one, if they exist; at the lattice's upper border
    // none does, and marking it would leave a vertex in no tetrahedron).
    unsigned whole_slots = 0;

    Layout(const Window& win, FaceRule face_rule, const graded3::Octree3* octree) : w(win), rule(face_rule), tree(octree) {
        plane_pair = win.grid.corner_w * win.grid.corner_h + win.grid.centre_w * win.grid.centre_h;
        for (const TetShape& s : shapes)
            for (int k : s.slot_in_cube) whole_slots |= 1u << k;
    }

    Neighbourhood around(const bcc::Ivec& m) const {
        Neighbourhood n;
        const std::int64_t corner = w.grid.index(m), centre = w.grid.index(bcc::add(m, {1, 1, 1}));
        for (int b = 0; b < 8; ++b) n.at[static_cast<std::size_t>(b)] = corner + (b & 1) + ((b >> 1) & 1) * w.grid.corner_w + (b >> 2) * plane_pair;
        n.at[8] = centre, n.at[9] = centre - 1, n.at[10] = centre - w.grid.centre_w, n.at[11] = centre - plane_pair;
        bool all = m[0] > 0 && m[1] > 0 && m[2] > 0, none = true;
        for (int k = 0; k < 12; ++k) {
            const bool exists = k < 9 || m[static_cast<std::size_t>(k - 9)] > 0;
            n.sign[static_cast<std::size_t>(k)] = exists ? w.sign[static_cast<std::size_t>(n.at[static_cast<std::size_t>(k)])] : 1;
            all = all && n.sign[static_cast<std::size_t>(k)] < 0;
            none = none && n.sign[static_cast<std::size_t>(k)] > 0;
        }
        n.all_inside = all, n.all_outside = none;
        return n;
    }

    // The parity rule's stencil of background tetrahedron `index` of the
    // cube, or nullptr when it does not exist or outputs nothing (no −
    // vertex; all_zero: its four vertices are zero); its sign code in `code`.
    const Plan* split(const bcc::Ivec& m, const Neighbourhood& n, int index, bool& all_zero, int& code) const {
        const TetShape& s = shapes[static_cast<std::size_t>(index)];
        if (m[static_cast<std::size_t>(index / 4)] == 0) return nullptr;
        int negative = 0, zero = 0;
        code = 0;
        for (int k = 3; k >= 0; --k) {
            const int sg = n.sign[static_cast<std::size_t>(s.slot_in_cube[static_cast<std::size_t>(k)])];
            code = code * 3 + sg + 1;
            negative += sg < 0, zero += sg == 0;
        }
        all_zero = zero == 4;
        return negative == 0 ? nullptr : &plans[static_cast<std::size_t>(code * 2 + s.parity)];
    }

    // The Delaunay face rule's stencil of background tetrahedron `index` of
    // the cube, with sign code `code` and quads: its signs and the cut
    // parameters of its (-, +) edges, in the local frame.
    const Plan* delaunay_split(const Neighbourhood& n, int index, int code) const {
        const TetShape& s = shapes[static_cast<std::size_t>(index)];
        std::array<int, 4> sign{};
        for (std::size_t k = 0; k < 4; ++k) sign[k] = n.sign[static_cast<std::size_t>(s.slot_in_cube[k])];
        std::array<double, 6> u{};
        unsigned from_upper = 0;
        for (std::size_t e = 0; e < 6; ++e) {
            const int i = bcc::tet_edges[e][0], j = bcc::tet_edges[e][1], lower = s.lower[e];
            if (sign[static_cast<std::size_t>(i)] * sign[static_cast<std::size_t>(j)] >= 0) continue;  // not cut
            u[e] = w.u(n.at[static_cast<std::size_t>(s.slot_in_cube[static_cast<std::size_t>(lower)])], s.slot[e]);
            if (lower != i) from_upper |= 1u << e;
        }
        const bcc::Diagonals d = delaunay_choice(sign, s.parity, u, from_upper);
        return &by_diagonals[static_cast<std::size_t>(code * diagonal_slots + diagonal_slot(d))];
    }
};

// Graded meshes: the templates of cube c's leaf (when c is its origin) that
// are output, those inside.  Each template of an inside leaf must have four
// vertices of one strict sign (octree3.hpp's invariant), else std::logic_error.
int inside_templates(const Layout& lay, const graded3::Cube& c, graded3::Templates& out) {
    // A leaf's templates all share its centre's sign: none is output unless it is inside.
    const int l = lay.tree->level_at(c);
    const int side = 1 << l;
    bcc::Ivec centre{};
    for (std::size_t a = 0; a < 3; ++a) {
        if (c[a] & (side - 1)) return 0;  // not the leaf's origin
        centre[a] = static_cast<int>(2 * c[a]) + side;
    }
    if (lay.w.sign[static_cast<std::size_t>(lay.w.grid.index(centre))] > 0) return 0;
    graded3::Templates all;  // (not zeroed: per cube)
    const int k = graded3::leaf_templates(*lay.tree, c, all);
    int n = 0;
    for (int i = 0; i < k; ++i) {
        int s0 = 0;
        for (const bcc::Ivec& q : all[static_cast<std::size_t>(i)]) {
            const int s = lay.w.sign[static_cast<std::size_t>(lay.w.grid.index(q))];
            if (s == 0 || (s0 != 0 && s != s0))
                throw std::logic_error("mesh3d graded: a template tetrahedron has a vertex on or across the level set "
                                       "(the finest-band invariant of octree3.hpp failed)");
            s0 = s;
        }
        if (s0 < 0) out[static_cast<std::size_t>(n++)] = all[static_cast<std::size_t>(i)];
    }
    return n;
}

// Graded meshes: which of cube c's background tetrahedra the stencils split
// (all without a tree); false when c belongs to a coarser leaf (templates only).
bool fine_cube(const Layout& lay, const graded3::Cube& c, unsigned& mask) {
    mask = 0xFFFu;
    if (!lay.tree) return true;
    if (lay.tree->level_at(c) > 0) return false;
    mask = graded3::uniform_mask(*lay.tree, c);
    return true;
}

// Pass A: the tetrahedra of each layer (prefix sums: layer l starts at
// start[l]) and the used marks.
std::vector<std::int64_t> count_and_mark(const Layout& lay, const CubeRange& range, Marks& marks) {
    const std::int64_t layers = range.hi[2] - range.lo[2];
    std::vector<std::int64_t> start(static_cast<std::size_t>(layers) + 1, 0);
    auto mark_point = [&](std::int64_t p) {
        std::atomic_ref<std::uint8_t>(marks.point[static_cast<std::size_t>(p)]).store(1, std::memory_order_relaxed);
    };
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t l = 0; l < layers; ++l) {
        std::int64_t count = 0;
        for_cubes_in_layer(range, range.lo[2] + l, [&](const bcc::Ivec& m, std::int64_t cx, std::int64_t cy) {
            unsigned mask = 0xFFFu;
            if (lay.tree) {
                graded3::Templates t;
                const int k = inside_templates(lay, {cx, cy, range.lo[2] + l}, t);
                count += k;
                for (int i = 0; i < k; ++i)
                    for (const bcc::Ivec& q : t[static_cast<std::size_t>(i)]) mark_point(lay.w.grid.index(q));
                if (!fine_cube(lay, {cx, cy, range.lo[2] + l}, mask)) return;
            }
            const Neighbourhood n = lay.around(m);
            if (n.all_outside) return;
            if (n.all_inside && mask == 0xFFFu) {
                count += 12;
                for (int k = 0; k < 12; ++k)
                    if (lay.whole_slots >> k & 1u) mark_point(n.at[static_cast<std::size_t>(k)]);
                return;
            }
            for (int index = 0; index < 12; ++index) {
                if (!(mask >> index & 1u)) continue;
                bool all_zero = false;
                int code = 0;
                const Plan* p = lay.split(m, n, index, all_zero, code);  // any face rule's count and points
                if (!p) continue;
                count += p->stencil.count;
                const TetShape& s = lay.shapes[static_cast<std::size_t>(index)];
                for (int q = 0; q < 10; ++q) {
                    if (!(p->uses >> q & 1u)) continue;
                    if (q < 4) {
                        mark_point(n.at[static_cast<std::size_t>(s.slot_in_cube[static_cast<std::size_t>(q)])]);
                        continue;
                    }
                    const int e = q - 4;
                    const std::int64_t owner = n.at[static_cast<std::size_t>(s.slot_in_cube[static_cast<std::size_t>(s.lower[static_cast<std::size_t>(e)])])];
                    std::atomic_ref<std::uint8_t>(marks.cut[static_cast<std::size_t>(owner)])
                        .fetch_or(static_cast<std::uint8_t>(1u << s.slot[static_cast<std::size_t>(e)]), std::memory_order_relaxed);
                }
            }
        });
        start[static_cast<std::size_t>(l) + 1] = count;
    }
    for (std::int64_t l = 0; l < layers; ++l) start[static_cast<std::size_t>(l) + 1] += start[static_cast<std::size_t>(l)];
    return start;
}

}  // namespace

Numbering number(const Grid& g, const Marks& marks) {
    const int planes = g.hi[2] - g.lo[2] + 1;
    std::vector<std::int64_t> np(static_cast<std::size_t>(planes) + 1, 0), nc(static_cast<std::size_t>(planes) + 1, 0);
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        std::int64_t a = 0, b = 0;
        for (std::int64_t p = g.plane_start[static_cast<std::size_t>(z)]; p < g.plane_start[static_cast<std::size_t>(z) + 1]; ++p)
            a += marks.point[static_cast<std::size_t>(p)], b += slot_count(marks.cut[static_cast<std::size_t>(p)]);
        np[static_cast<std::size_t>(z) + 1] = a, nc[static_cast<std::size_t>(z) + 1] = b;
    }
    for (int z = 0; z < planes; ++z) np[static_cast<std::size_t>(z) + 1] += np[static_cast<std::size_t>(z)], nc[static_cast<std::size_t>(z) + 1] += nc[static_cast<std::size_t>(z)];
    Numbering out;
    out.points = np.back(), out.cuts = nc.back();
    if (out.points + out.cuts >= INT32_MAX)
        throw OptionError("spacing", "the 3D mesh would have more than 2^31 vertices; choose a larger {spacing} or mesh in blocks (mesh3d_block)");
    const std::size_t n = static_cast<std::size_t>(g.count());
    out.id.resize(n), out.cut_id.resize(n);  // every element written below
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        std::int64_t a = np[static_cast<std::size_t>(z)], b = out.points + nc[static_cast<std::size_t>(z)];
        for (std::int64_t p = g.plane_start[static_cast<std::size_t>(z)]; p < g.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
            out.id[static_cast<std::size_t>(p)] = static_cast<std::int32_t>(a), out.cut_id[static_cast<std::size_t>(p)] = static_cast<std::int32_t>(b);
            a += marks.point[static_cast<std::size_t>(p)], b += slot_count(marks.cut[static_cast<std::size_t>(p)]);
        }
    }
    return out;
}

namespace {

// The used vertices' positions, level-set flags and (blocks) global keys.
void place_vertices(const Window& w, const Marks& marks, const Numbering& num, bool keys, Emitted& out) {
    const Grid& g = w.grid;
    const int planes = g.hi[2] - g.lo[2] + 1;
    const Grid whole = Grid::whole(g.lattice);
    const std::int64_t lattice_points = g.lattice.point_count();
    std::int64_t warped = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : warped)
    for (int z = 0; z < planes; ++z) {
        for (std::int64_t p = g.plane_start[static_cast<std::size_t>(z)]; p < g.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
            const std::uint8_t cut = marks.cut[static_cast<std::size_t>(p)];
            if (!marks.point[static_cast<std::size_t>(p)] && !cut) continue;
            const bcc::Ivec q = g.point_in_plane(z, p);
            const std::int64_t global = keys ? whole.index(q) : 0;
            if (marks.point[static_cast<std::size_t>(p)]) {
                const std::size_t v = static_cast<std::size_t>(num.id[static_cast<std::size_t>(p)]);
                out.vertices[v] = w.warp[static_cast<std::size_t>(p)] != bcc::stay ? w.point_position(p) : w.lattice_position(q);
                out.on_level_set[v] = w.sign[static_cast<std::size_t>(p)] == 0;
                warped += w.warp[static_cast<std::size_t>(p)] != bcc::stay;
                if (keys) out.vertex_key[v] = static_cast<std::uint64_t>(global);
            }
            std::size_t v = static_cast<std::size_t>(num.cut_id[static_cast<std::size_t>(p)]);
            for (int s = 0; s < 7; ++s) {
                if (!(cut >> s & 1u)) continue;
                out.vertices[v] = w.cut_position(q, s, w.u(p, s));
                out.on_level_set[v] = 1;
                if (keys) out.vertex_key[v] = static_cast<std::uint64_t>(lattice_points + 7 * global + s);
                ++v;
            }
        }
    }
    out.warped_vertices = warped;
}

// Pass B: the tetrahedra, with (blocks) their keys, and the sparse lists.
// The key check of verify for one output background tetrahedron: its key's
// claim, or nothing (counted in `uncovered`) if the claims do not list the
// key; its code in *code.
std::optional<BccKeyClaim> check_key(const Layout& lay, const BccKeyClaims& claims, const bcc::Ivec& m, const Neighbourhood& n, int index,
                                     std::int64_t& uncovered, std::string& first, std::string* code) {
    const TetShape& s = lay.shapes[static_cast<std::size_t>(index)];
    std::array<bcc::Ivec, 4> p{};
    std::array<int, 4> sign{}, warp{};
    for (std::size_t k = 0; k < 4; ++k) {
        const std::size_t slot = static_cast<std::size_t>(s.slot_in_cube[k]);
        p[k] = bcc::add(m, s.offset[k]);
        sign[k] = n.sign[slot];
        warp[k] = lay.w.warp[static_cast<std::size_t>(n.at[slot])];
    }
    const bcc::Config key = bcc::key_of(p, sign, warp);
    *code = bcc::code_of(key);
    std::optional<BccKeyClaim> claim = claims.claim(key);
    if (claim) return claim;
    ++uncovered;
#pragma omp critical
    if (first.empty()) first = *code;
    return std::nullopt;
}

// verify's per-key check of the output tetrahedra [t0, t1) of one
// background tetrahedron against its key's claim (vertices already placed).
void check_claim(const Emitted& out, std::int64_t t0, std::int64_t t1, const BccKeyClaim& b, const std::string& code,
                 std::int64_t& failures, std::string& first) {
    const double c_min = b.cos2_min, c_max = b.cos2_max;
    for (std::int64_t t = t0; t < t1; ++t) {
        const auto& tet = out.tets[static_cast<std::size_t>(t)];
        std::array<Point3, 4> q{};
        for (std::size_t k = 0; k < 4; ++k) q[k] = out.vertices[static_cast<std::size_t>(tet[k])];
        if (key_claim_holds(q, c_min, c_max)) continue;
        ++failures;
#pragma omp critical
        if (first.empty()) first = code;
    }
}

// The 12 tetrahedra of a cube whose background tetrahedra are all inside
// (Neighbourhood::all_inside), none on the lattice's cut-off: each whole, in
// the all-− stencil's vertex order, as the general path below writes them.
void write_whole_cube(const Layout& lay, const Neighbourhood& n, const Numbering& num, bool keys, std::uint64_t cube_key, std::int64_t& t,
                      Emitted& out) {
    const bcc::OutTet& o = lay.plans[0].stencil.tet[0];
    for (std::size_t index = 0; index < 12; ++index, ++t) {
        const TetShape& s = lay.shapes[index];
        std::array<std::int32_t, 4> v{};
        for (std::size_t k = 0; k < 4; ++k) v[k] = num.id[static_cast<std::size_t>(n.at[static_cast<std::size_t>(s.slot_in_cube[static_cast<std::size_t>(o[k])])])];
        out.tets[static_cast<std::size_t>(t)] = v;
        if (keys) out.tet_key[static_cast<std::size_t>(t)] = cube_key + index * 4;
    }
}

// Graded meshes: the inside templates of cube c's leaf, written from t on
// (vertex ids of their lattice points); with a claim, each checked against it.
void write_templates(const Layout& lay, const graded3::Cube& c, const Numbering& num, const std::optional<BccKeyClaim>& claim,
                     std::int64_t& t, std::int64_t& failures, std::string& first, Emitted& out) {
    graded3::Templates tt;
    const int k = inside_templates(lay, c, tt);
    for (int i = 0; i < k; ++i, ++t) {
        std::array<std::int32_t, 4> v{};
        std::array<Point3, 4> q{};
        for (std::size_t j = 0; j < 4; ++j) {
            const bcc::Ivec& p = tt[static_cast<std::size_t>(i)][j];
            v[j] = num.id[static_cast<std::size_t>(lay.w.grid.index(p))];
            if (claim) q[j] = lay.w.lattice_position(p);
        }
        out.tets[static_cast<std::size_t>(t)] = v;
        if (claim && !key_claim_holds(q, claim->cos2_min, claim->cos2_max)) {
            ++failures;
#pragma omp critical
            if (first.empty()) first = "template";
        }
    }
}

void write_tets(const Layout& lay, const CubeRange& range, const Marks& marks, const Numbering& num,
                std::span<const std::int64_t> start, bool keys, const BccKeyClaims* verify, Emitted& out) {
    const Lattice3& L = lay.w.grid.lattice;
    const std::int64_t layers = range.hi[2] - range.lo[2];
    std::vector<std::vector<CutOff>> edge(static_cast<std::size_t>(layers));
    std::int64_t uncovered = 0, failures = 0, all_zero_left_out = 0, cyclic = 0, templates = 0;
    const std::optional<BccKeyClaim> template_claim = verify ? verify->template_claim : std::nullopt;
    // A whole background tetrahedron's key (four − vertices, none warped; the
    // same for every index), looked up once.
    std::string whole_code;
    std::optional<BccKeyClaim> whole_bound;
    if (verify) {
        const bcc::Config whole = bcc::key_of(lay.shapes[0].offset, {-1, -1, -1, -1}, {bcc::stay, bcc::stay, bcc::stay, bcc::stay});
        whole_code = bcc::code_of(whole);
        whole_bound = verify->claim(whole);
        if (!whole_bound)
            throw std::logic_error("mesh3d verify: " + verify->source + " does not list the key " + whole_code +
                                   " of a whole background tetrahedron");
    }
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : uncovered, failures, all_zero_left_out, cyclic, templates)
    for (std::int64_t l = 0; l < layers; ++l) {
        std::int64_t t = start[static_cast<std::size_t>(l)];
        const std::int64_t cz = range.lo[2] + l;
        for_cubes_in_layer(range, cz, [&](const bcc::Ivec& m, std::int64_t cx, std::int64_t cy) {
            unsigned mask = 0xFFFu;
            if (lay.tree) {
                const std::int64_t t0 = t;
                write_templates(lay, {cx, cy, cz}, num, template_claim, t, failures, out.first_key_claim_failure, out);
                templates += t - t0;
                if (!fine_cube(lay, {cx, cy, cz}, mask)) return;
            }
            const Neighbourhood n = lay.around(m);
            if (n.all_outside) return;
            const bool near_edge = cx < 2 || cy < 2 || cz < 2 || cx >= L.cubes[0] - 2 || cy >= L.cubes[1] - 2 || cz >= L.cubes[2] - 2;
            const std::uint64_t cube_key = static_cast<std::uint64_t>((cz * L.cubes[1] + cy) * L.cubes[0] + cx) * 48;
            if (n.all_inside && mask == 0xFFFu && !near_edge && !verify) return write_whole_cube(lay, n, num, keys, cube_key, t, out);
            for (int index = 0; index < 12; ++index) {
                if (!(mask >> index & 1u)) continue;
                const TetShape& s = lay.shapes[static_cast<std::size_t>(index)];
                bool all_zero = false;
                int sign_code = 0;
                const Plan* p = n.all_inside ? &lay.plans[0] : lay.split(m, n, index, all_zero, sign_code);
                all_zero_left_out += all_zero;
                if (!p) continue;
                if (p->quads && lay.rule == FaceRule::delaunay) {
                    const Plan* d = lay.delaunay_split(n, index, sign_code);
                    cyclic += d->cyclic;  // never, with exact signs (generic_bcc.hpp); reported below
                    if (!d->cyclic) p = d;
                }
                std::optional<BccKeyClaim> bound;
                std::string code;
                if (verify) bound = n.all_inside ? whole_bound : check_key(lay, *verify, m, n, index, uncovered, out.first_uncovered, &code);
                const std::int64_t t0 = t;
                std::array<std::int32_t, 10> vid{};
                for (int q = 0; q < 10; ++q) {
                    if (!(p->uses >> q & 1u)) continue;
                    if (q < 4) {
                        vid[static_cast<std::size_t>(q)] = num.id[static_cast<std::size_t>(n.at[static_cast<std::size_t>(s.slot_in_cube[static_cast<std::size_t>(q)])])];
                        continue;
                    }
                    const std::size_t owner = static_cast<std::size_t>(n.at[static_cast<std::size_t>(s.slot_in_cube[static_cast<std::size_t>(s.lower[static_cast<std::size_t>(q - 4)])])]);
                    const int slot = s.slot[static_cast<std::size_t>(q - 4)];
                    vid[static_cast<std::size_t>(q)] = num.cut_id[owner] + slot_count(marks.cut[owner] & ((1u << slot) - 1));
                }
                unsigned missing = 0;  // bit v: no background tetrahedron across the face without v
                if (near_edge)
                    for (int v = 0; v < 4; ++v) missing |= in_lattice(L, bcc::add(m, s.across[static_cast<std::size_t>(v)])) ? 0u : 1u << v;
                for (int k = 0; k < p->stencil.count; ++k, ++t) {
                    const bcc::OutTet& o = p->stencil.tet[static_cast<std::size_t>(k)];
                    out.tets[static_cast<std::size_t>(t)] = {vid[o[0]], vid[o[1]], vid[o[2]], vid[o[3]]};
                    if (keys) out.tet_key[static_cast<std::size_t>(t)] = cube_key + static_cast<std::uint64_t>(index * 4 + k);
                    if (missing) {
                        unsigned faces = 0;
                        for (int f = 0; f < 4; ++f)
                            if (p->face_on[static_cast<std::size_t>(k)][static_cast<std::size_t>(f)] & missing) faces |= 1u << f;
                        if (faces) edge[static_cast<std::size_t>(l)].push_back({t, static_cast<std::uint8_t>(faces)});
                    }
                }
                if (bound) check_claim(out, t0, t, *bound, n.all_inside ? whole_code : code, failures, out.first_key_claim_failure);
            }
        });
    }
    for (const auto& e : edge) out.cut_off.insert(out.cut_off.end(), e.begin(), e.end());
    out.all_zero_left_out = all_zero_left_out;
    out.uncovered_keys = uncovered;
    out.key_claim_failures = failures;
    out.template_tets = templates;
    if (cyclic > 0)
        throw std::logic_error("mesh3d: the Delaunay face rule turned " + std::to_string(cyclic) + " prisms' three quads the same way");
}

}  // namespace

bool key_claim_holds(const std::array<Point3, 4>& q, double cos2_min, double cos2_max) {
    std::array<bcc::Vec<double>, 4> p{};
    for (std::size_t k = 0; k < 4; ++k) p[k] = {q[k].x, q[k].y, q[k].z};
    const auto f = bcc::dihedral_forms<double>(p);
    bool ok = f.volume6 > 0;
    for (std::size_t k = 0; k < 6; ++k) {
        const double d = f.dot[k], d2 = d * d;
        ok = ok && (d <= 0 || d2 <= cos2_min * f.nn[k]) && (d >= 0 || d2 <= cos2_max * f.nn[k]);
    }
    return ok;
}

Emitted emit_tets(const Window& w, const CubeRange& range, bool keys, std::uint64_t max_memory, FaceRule rule, const BccKeyClaims* verify,
                  const graded3::Octree3* tree) {
    const Layout lay(w, rule, tree);
    const std::size_t n = static_cast<std::size_t>(w.grid.count());
    Marks marks{ZeroBuffer<std::uint8_t>(n), ZeroBuffer<std::uint8_t>(n)};
    const std::vector<std::int64_t> start = count_and_mark(lay, range, marks);
    const std::int64_t tet_count = start.back();
    if (tet_count >= INT32_MAX)
        throw OptionError("spacing", "the 3D mesh would have more than 2^31 tetrahedra; choose a larger {spacing} or mesh in blocks (mesh3d_block)");
    Numbering num = number(w.grid, marks);
    const std::int64_t vertex_count = num.points + num.cuts;
    // The output: 16 bytes a tetrahedron (+4 for its region, written later,
    // +8 for a block's keys), 25 a vertex (+8 with keys).
    check_memory(static_cast<std::uint64_t>(tet_count) * (20 + (keys ? 8 : 0)) + static_cast<std::uint64_t>(vertex_count) * 33,
                 max_memory, "the 3D mesh of " + std::to_string(tet_count) + " tetrahedra", "about 24 bytes a tetrahedron",
                 "choose a larger {spacing}");
    Emitted out;
    out.cut_points = num.cuts;
    out.vertices.resize(static_cast<std::size_t>(vertex_count));  // each written once by place_vertices
    out.on_level_set.resize(static_cast<std::size_t>(vertex_count));
    if (keys) out.vertex_key.resize(static_cast<std::size_t>(vertex_count));
    place_vertices(w, marks, num, keys, out);
    out.tets.resize(static_cast<std::size_t>(tet_count));  // each written once by write_tets
    if (keys) out.tet_key.resize(static_cast<std::size_t>(tet_count));
    write_tets(lay, range, marks, num, start, keys, verify, out);
    return out;
}

}  // namespace warpmesh::uniform3d
