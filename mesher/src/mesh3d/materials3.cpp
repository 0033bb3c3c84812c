// materials3.cpp — the multi-material 3D mesher (mesh3d.hpp:
// mesh_bcc_materials, mesh_bcc_materials_block).  On a window of the
// lattice — the whole lattice, or a block's cubes grown by a halo until no
// point of the block's is tainted (assembly3.cpp: block_window) — every
// point's material, the cut points between materials, closest-first warping
// (warp3.cpp, unchanged: a cut edge is one whose ends' materials differ),
// then every background tetrahedron of the range's cubes split by
// generic_bcc_materials.hpp's rule, in two passes over the cube layers as
// tets3.cpp does (count and mark, then number and write).  The boundary and
// the interfaces are the faces whose vertices all lie on interfaces
// (assembly3.cpp: find_boundary), found on the whole mesh or, for blocks,
// after merge_tet_blocks.  Every vertex and tetrahedron has a global key
// (GlobalKeys) whose order is the whole mesh's order, so that the whole
// lattice is the one-window case and blocks merge into it exactly.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <stdexcept>

#include "mesh3d/graded/octree3.hpp"
#include "uniform3d.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"  // key_of
#include "warpmesh/mesh3d/generic_bcc_materials.hpp"
#include "warpmesh/mesh3d/graded.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {
namespace uniform3d {
namespace {

using Key3 = std::array<std::int64_t, 3>;

// The split of one background tetrahedron: output tetrahedra over its 15
// local points (generic_bcc_materials.hpp) and their material codes.  Only
// the first `count` entries of the arrays are written (pass B makes a split
// for every background tetrahedron near an interface: not zeroed).
struct Split {
    int count = 0;
    std::array<bcc::OutTet, 24> tet;
    std::array<std::uint16_t, 24> material;
    std::array<std::uint8_t, 24> side;  // 0, 1: a two-material side's letter; junction_side; fill_side
    std::array<int, 4> letter{};
    bool all_zero = false, junction = false, void_left = false;
};
inline constexpr std::uint8_t junction_side = 2, fill_side = 3;

// What a split outputs, as pass A needs it: how many tetrahedra, which of
// the 15 local points they use (bit q) and the split's flags.
struct Footprint {
    int count = 0;
    unsigned used = 0;
    bool all_zero = false, junction = false, void_left = false;
};

// Bit q set for every local point q of the first `count` tetrahedra of t.
template <std::size_t N>
unsigned used_points(const std::array<bcc::OutTet, N>& t, int count) {
    unsigned used = 0;
    for (int k = 0; k < count; ++k)
        for (const std::uint8_t q : t[static_cast<std::size_t>(k)]) used |= 1u << q;
    return used;
}
inline constexpr int void_fill = -2;

// The junction stencils by (letters, parity): letters coded (l + 1) 5^i.
const std::vector<bcc::MaterialStencil>& junction_table() {
    static const std::vector<bcc::MaterialStencil> table = [] {
        std::vector<bcc::MaterialStencil> t(625 * 2);
        for (int code = 0; code < 625; ++code) {
            std::array<int, 4> letter{};
            for (int i = 0, c = code; i < 4; ++i, c /= 5) letter[static_cast<std::size_t>(i)] = c % 5 - 1;
            if (bcc::letter_count(letter) < 3) continue;
            for (int parity = 0; parity < 2; ++parity) t[static_cast<std::size_t>(code * 2 + parity)] = bcc::junction_stencil(letter, parity);
        }
        return t;
    }();
    return table;
}

// The global keys (mesh3d.hpp, "Blocks"), whose order is the whole mesh's
// vertex and tetrahedron order.  With P the lattice's points:
//   lattice point q                  index(q)
//   cut point (lower end q, slot s)  P + 7 index(q) + s
//   face point of a junction face    8P + 49 index(q0) + 7 s1 + s2: q0 the
//                                    face's lowest point, s1 < s2 the forward
//                                    slots of its two edges from q0
//   centre of background tet (c, i)  57P + 12 c + i: c the cube's index in
//                                    (z, y, x) order, i background_tet's index
//   output tetrahedron k of (c, i)   24 (12 c + i) + k
struct GlobalKeys {
    struct FaceName {
        int lowest = 0, s1 = 0, s2 = 0;  // q0's local vertex, the slots
    };
    Grid whole;
    std::array<std::int64_t, 3> cubes{};
    std::uint64_t P = 0;
    std::array<std::array<FaceName, 4>, 12> face_name{};  // per background tetrahedron index, face (without vertex f)

    explicit GlobalKeys(const Lattice3& L) : whole(Grid::whole(L)), cubes(L.cubes), P(static_cast<std::uint64_t>(L.point_count())) {
        for (std::size_t index = 0; index < 12; ++index) {
            const TetShape& sh = tet_shapes()[index];
            for (int f = 0; f < 4; ++f)
                for (int v = 0; v < 4; ++v) {
                    if (v == f) continue;
                    const int a = (v + 1) % 4 == f ? (v + 2) % 4 : (v + 1) % 4, b = 6 - f - v - a;
                    const std::size_t ea = static_cast<std::size_t>(bcc::edge_index(v, a)), eb = static_cast<std::size_t>(bcc::edge_index(v, b));
                    if (sh.lower[ea] != v || sh.lower[eb] != v) continue;  // v is not the face's lowest point
                    face_name[index][static_cast<std::size_t>(f)] = {v, std::min(sh.slot[ea], sh.slot[eb]), std::max(sh.slot[ea], sh.slot[eb])};
                }
        }
    }
    std::uint64_t point(const bcc::Ivec& q) const { return static_cast<std::uint64_t>(whole.index(q)); }
    std::uint64_t cut(const bcc::Ivec& q, int slot) const { return P + 7 * point(q) + static_cast<std::uint64_t>(slot); }
    // Face f of background tetrahedron `index` of cube m.
    std::uint64_t face(const bcc::Ivec& m, int index, int f) const {
        const FaceName& n = face_name[static_cast<std::size_t>(index)][static_cast<std::size_t>(f)];
        const bcc::Ivec q0 = bcc::add(m, tet_shapes()[static_cast<std::size_t>(index)].offset[static_cast<std::size_t>(n.lowest)]);
        return 8 * P + 49 * point(q0) + static_cast<std::uint64_t>(7 * n.s1 + n.s2);
    }
    std::uint64_t background(const bcc::Ivec& m, int index) const {
        const std::int64_t c = ((m[2] / 2) * cubes[1] + m[1] / 2) * cubes[0] + m[0] / 2;
        return static_cast<std::uint64_t>(12 * c + index);
    }
    std::uint64_t centre(const bcc::Ivec& m, int index) const { return 57 * P + background(m, index); }
    std::uint64_t tet(const bcc::Ivec& m, int index, int k) const { return 24 * background(m, index) + static_cast<std::uint64_t>(k); }
};

// The cubes `range` of a warped window and what they output.
struct MaterialLayout {
    const Window& w;
    const MaterialField3& field;
    std::optional<BccKeyClaim> fill;   // all-zero background tetrahedra meeting it are output
    std::span<const std::uint16_t> mat;
    std::vector<std::uint8_t> output;  // per material code: output it
    bool merge_outside = false;        // the background dropped: it and the outside are one (no cut between them)
    const std::array<TetShape, 12>& shapes = tet_shapes();
    std::span<const Plan> plans = uniform3d::plans();  // looked up once, not per tetrahedron
    std::int64_t plane_pair = 0;
    CubeRange range;
    GlobalKeys keys;
    bool keyed = false;                // write every vertex's and tetrahedron's key (blocks)
    const graded3::Octree3* tree = nullptr;  // graded meshes (whole lattice, no keys)

    MaterialLayout(const Window& win, const MaterialField3& f, const std::optional<BccKeyClaim>& fill_claim,
                   std::span<const std::uint16_t> material, bool keep_background, const CubeRange& cubes, bool with_keys,
                   const graded3::Octree3* octree = nullptr)
        : w(win), field(f), fill(fill_claim), mat(material), output(65536, 0), merge_outside(!keep_background), range(cubes),
          keys(win.grid.lattice), keyed(with_keys), tree(octree) {
        plane_pair = win.grid.corner_w * win.grid.corner_h + win.grid.centre_w * win.grid.centre_h;
        for (int m = keep_background ? 0 : 1; m < f.count(); ++m) output[static_cast<std::size_t>(m)] = 1;
    }
    // The window indices of the 12 points around cube m, by neighbourhood
    // slot (TetShape::slot_in_cube): two index computations a cube.
    using CubePoints = std::array<std::int64_t, 12>;
    CubePoints cube_points(const bcc::Ivec& m) const {
        const std::int64_t corner = w.grid.index(m), centre = w.grid.index(bcc::add(m, {1, 1, 1}));
        CubePoints c;
        for (int k = 0; k < 8; ++k) c[static_cast<std::size_t>(k)] = corner + (k & 1) + ((k >> 1) & 1) * w.grid.corner_w + (k >> 2) * plane_pair;
        c[8] = centre, c[9] = centre - 1, c[10] = centre - w.grid.centre_w, c[11] = centre - plane_pair;
        return c;
    }
    std::array<std::int64_t, 4> points(const CubePoints& c, int index) const {
        std::array<std::int64_t, 4> p{};
        for (std::size_t k = 0; k < 4; ++k) p[k] = c[static_cast<std::size_t>(shapes[static_cast<std::size_t>(index)].slot_in_cube[k])];
        return p;
    }
    void push(Split& s, const bcc::OutTet& t, std::uint16_t material, std::uint8_t side) const {
        if (!output[material]) return;
        s.tet[static_cast<std::size_t>(s.count)] = t;
        s.side[static_cast<std::size_t>(s.count)] = side;
        s.material[static_cast<std::size_t>(s.count++)] = material;
    }
    // The letters of background tetrahedron p's points (letters_of, with
    // warped points and the outside merged as `code` does) and each letter's
    // material code in material_of.
    std::array<int, 4> letters(const std::array<std::int64_t, 4>& p, std::array<std::uint16_t, 4>& material_of) const;
    Split split(const std::array<std::int64_t, 4>& p, int parity) const;
    // What split(p, parity) outputs, for pass A: its count, the local points
    // its tetrahedra use and its flags, from per-stencil tables (the same
    // stencils, so the same figures) instead of writing the tetrahedra.
    Footprint footprint(const std::array<std::int64_t, 4>& p, int parity) const;
    // Window point p's material code (the outside merged into the background when it is dropped).
    std::uint16_t code(std::int64_t p) const {
        const std::uint16_t c = mat[static_cast<std::size_t>(p)];
        return merge_outside && c == outside_code ? 0 : c;
    }
    // Graded meshes: the output templates of cube c's leaf (none unless c is
    // its origin and the leaf's material is output), that material in
    // `material`.  Each template's four vertices must be unwarped and of the
    // leaf's material (octree3.hpp's invariant, several materials), else
    // std::logic_error.
    int leaf_templates(const graded3::Cube& c, graded3::Templates& out, std::uint16_t& material) const;
    // Graded meshes: which of cube c's background tetrahedra the split rule
    // handles (all without a tree); false when c lies in a coarser leaf.
    bool fine_cube(const graded3::Cube& c, unsigned& mask) const {
        mask = 0xFFFu;
        if (!tree) return true;
        if (tree->level_at(c) > 0) return false;
        mask = graded3::uniform_mask(*tree, c);
        return true;
    }
    // An all-zero background tetrahedron's material (mesh3d.hpp): the
    // material at its centroid if it is output and the warped tetrahedron
    // meets the fill claim with a margin; -1 if that material is not output
    // (left out, as it would be anyway); void_fill if it is but the claim
    // fails (left out: a void inside the materials).
    int fill_material(const std::array<std::int64_t, 4>& p) const;
    // A cube whose 12 background tetrahedra all exist and whose 12 points
    // (TetShape::slot_in_cube) are unwarped and of one material: that
    // material's code (its tetrahedra are whole), else -1.
    int whole_cube(const bcc::Ivec& m, const CubePoints& points) const {
        if (m[0] == 0 || m[1] == 0 || m[2] == 0) return -1;
        int code = -1;
        for (const std::int64_t q : points) {
            const std::size_t p = static_cast<std::size_t>(q);
            if (w.warp[p] != bcc::stay) return -1;
            int c = mat[p];
            if (merge_outside && c == outside_code) c = 0;
            if (code >= 0 && c != code) return -1;
            code = c;
        }
        return code;
    }
};

int MaterialLayout::fill_material(const std::array<std::int64_t, 4>& p) const {
    std::array<Point3, 4> q{};
    Point3 c{0, 0, 0};
    for (std::size_t k = 0; k < 4; ++k) {
        q[k] = w.point_position(p[k]);
        c.x += 0.25 * q[k].x, c.y += 0.25 * q[k].y, c.z += 0.25 * q[k].z;
    }
    const int m = field.material_at(c);
    if (m == outside_material || !output[static_cast<std::size_t>(m)]) return -1;
    // The claim tightened by a relative 1e-9, so that double rounding in the
    // forms cannot let a tetrahedron just outside it through.
    if (!fill || !key_claim_holds(q, fill->cos2_min * (1 - 1e-9), fill->cos2_max * (1 - 1e-9))) return void_fill;
    return m;
}

int MaterialLayout::leaf_templates(const graded3::Cube& c, graded3::Templates& out, std::uint16_t& material) const {
    const int side = 1 << tree->level_at(c);
    bcc::Ivec centre{};
    for (std::size_t a = 0; a < 3; ++a) {
        if (c[a] & (side - 1)) return 0;  // not the leaf's origin
        centre[a] = static_cast<int>(2 * c[a]) + side;
    }
    material = code(w.grid.index(centre));
    if (!output[material]) return 0;  // a leaf's templates all have its centre's material
    const int k = graded3::leaf_templates(*tree, c, out);
    for (int i = 0; i < k; ++i)
        for (const bcc::Ivec& q : out[static_cast<std::size_t>(i)]) {
            const std::int64_t p = w.grid.index(q);
            if (w.warp[static_cast<std::size_t>(p)] != bcc::stay || code(p) != material)
                throw std::logic_error("mesh3d graded materials: a template tetrahedron has a warped vertex or two materials "
                                       "(the finest-band invariant of octree3.hpp failed)");
        }
    return k;
}

std::array<int, 4> MaterialLayout::letters(const std::array<std::int64_t, 4>& p, std::array<std::uint16_t, 4>& material_of) const {
    std::array<std::uint16_t, 4> m{};
    std::array<bool, 4> warped{};
    for (std::size_t k = 0; k < 4; ++k) {
        m[k] = code(p[k]);
        warped[k] = w.warp[static_cast<std::size_t>(p[k])] != bcc::stay;
    }
    const std::array<int, 4> letter = bcc::letters_of(m, warped);
    material_of = {};
    for (std::size_t i = 0; i < 4; ++i)
        if (letter[i] >= 0) material_of[static_cast<std::size_t>(letter[i])] = m[i];
    return letter;
}

// The junction stencil's code of letters (l + 1) 5^i, and a two-material
// side's one-region code Σ (sign + 1) 3^i (its letter −, the other +).
int junction_code(const std::array<int, 4>& letter) {
    int code = 0;
    for (int i = 3; i >= 0; --i) code = code * 5 + letter[static_cast<std::size_t>(i)] + 1;
    return code;
}
int side_code(const std::array<int, 4>& letter, int side) {
    int code = 0;
    for (int i = 3; i >= 0; --i) {
        const int l = letter[static_cast<std::size_t>(i)];
        code = code * 3 + (l < 0 ? 1 : l == side ? 0 : 2);
    }
    return code;
}

Split MaterialLayout::split(const std::array<std::int64_t, 4>& p, int parity) const {
    std::array<std::uint16_t, 4> material_of{};
    const std::array<int, 4> letter = letters(p, material_of);
    const int k = bcc::letter_count(letter);
    Split s;
    s.letter = letter;
    if (k == 0) {
        s.all_zero = true;
        const int f = fill_material(p);
        if (f >= 0) push(s, bcc::OutTet{0, 1, 2, 3}, static_cast<std::uint16_t>(f), fill_side);
        s.void_left = f == void_fill;
        return s;
    }
    if (k >= 3) {
        const bcc::MaterialStencil& st = junction_table()[static_cast<std::size_t>(junction_code(letter) * 2 + parity)];
        s.junction = true;
        for (int t = 0; t < st.count; ++t)
            push(s, st.tet[static_cast<std::size_t>(t)].tet, material_of[static_cast<std::size_t>(st.tet[static_cast<std::size_t>(t)].letter)], junction_side);
        return s;
    }
    // One or two letters: the one-region stencil of each side (code = Σ (sign + 1) 3^i).
    for (int side = 0; side < k; ++side) {
        const bcc::Stencil& st = plans[static_cast<std::size_t>(side_code(letter, side) * 2 + parity)].stencil;
        for (int t = 0; t < st.count; ++t) push(s, st.tet[static_cast<std::size_t>(t)], material_of[static_cast<std::size_t>(side)], static_cast<std::uint8_t>(side));
    }
    return s;
}

// Per one-region plan (plans()'s index code * 2 + parity): its stencil's
// count and used points.
const std::vector<Footprint>& side_footprints() {
    static const std::vector<Footprint> table = [] {
        std::vector<Footprint> t;
        for (const Plan& p : plans())
            t.push_back({p.stencil.count, used_points(p.stencil.tet, p.stencil.count)});
        return t;
    }();
    return table;
}

// Per junction stencil (junction_table()'s index) and letter: the count and
// used points of its tetrahedra of that letter.  The table also holds codes
// split() never meets (letters not numbered by first appearance, such as
// three warped vertices and letter 2), whose stencils may hold tetrahedra
// of letter -1 (a face of three warped vertices); those are left out.
const std::vector<std::array<Footprint, 4>>& junction_footprints() {
    static const std::vector<std::array<Footprint, 4>> table = [] {
        std::vector<std::array<Footprint, 4>> t(junction_table().size());
        for (std::size_t i = 0; i < t.size(); ++i) {
            const bcc::MaterialStencil& st = junction_table()[i];
            for (int k = 0; k < st.count; ++k) {
                const int letter = st.tet[static_cast<std::size_t>(k)].letter;
                if (letter < 0) continue;
                Footprint& f = t[i][static_cast<std::size_t>(letter)];
                ++f.count;
                for (const std::uint8_t q : st.tet[static_cast<std::size_t>(k)].tet) f.used |= 1u << q;
            }
        }
        return t;
    }();
    return table;
}

Footprint MaterialLayout::footprint(const std::array<std::int64_t, 4>& p, int parity) const {
    std::array<std::uint16_t, 4> material_of{};
    const std::array<int, 4> letter = letters(p, material_of);
    const int k = bcc::letter_count(letter);
    Footprint f;
    const auto add = [&](const Footprint& g, std::uint16_t material) {
        if (output[material]) f.count += g.count, f.used |= g.used;
    };
    if (k == 0) {  // the fill's material needs the field: split it
        const Split s = split(p, parity);
        return {s.count, used_points(s.tet, s.count), true, false, s.void_left};
    }
    if (k >= 3) {
        const std::array<Footprint, 4>& by_letter = junction_footprints()[static_cast<std::size_t>(junction_code(letter) * 2 + parity)];
        for (int l = 0; l < k; ++l) add(by_letter[static_cast<std::size_t>(l)], material_of[static_cast<std::size_t>(l)]);
        f.junction = true;
        return f;
    }
    for (int side = 0; side < k; ++side)
        add(side_footprints()[static_cast<std::size_t>(side_code(letter, side) * 2 + parity)], material_of[static_cast<std::size_t>(side)]);
    return f;
}

// Whether cube m touches the lattice's cut-off (its tetrahedra may have
// faces there: the general path records them).
bool in_lattice_edge(const Lattice3& L, const bcc::Ivec& m) {
    for (std::size_t a = 0; a < 3; ++a)
        if (m[a] < 4 || m[a] >= 2 * L.cubes[a] - 4) return true;
    return false;
}

// A junction face's point: its global key and its face's three lattice
// points (window indices, ascending: the (z, y, x) order).
struct FacePoint {
    std::uint64_t key = 0;
    Key3 points{};
    bool operator<(const FacePoint& o) const { return key < o.key; }
};

FacePoint face_point_of(const MaterialLayout& lay, const bcc::Ivec& m, int index, const std::array<std::int64_t, 4>& p, int f) {
    FacePoint fp;
    fp.key = lay.keys.face(m, index, f);
    for (int i = 0, n = 0; i < 4; ++i)
        if (i != f) fp.points[static_cast<std::size_t>(n++)] = p[static_cast<std::size_t>(i)];
    std::sort(fp.points.begin(), fp.points.end());
    return fp;
}

// Pass A's per-layer results (and, summed, the window's).
struct LayerCount {
    std::int64_t tets = 0, centres = 0, all_zero = 0, filled = 0, voids = 0, junctions = 0, junction_tets = 0, templates = 0;
    std::vector<FacePoint> faces;  // face points used
};

// Pass A for one split background tetrahedron (index, lattice points p) of cube m.
void count_split(const MaterialLayout& lay, const bcc::Ivec& m, int index, const std::array<std::int64_t, 4>& p, const Footprint& s,
                 Marks& marks, LayerCount& c) {
    const TetShape& sh = lay.shapes[static_cast<std::size_t>(index)];
    c.all_zero += s.all_zero;
    c.filled += s.all_zero && s.count > 0;
    c.voids += s.void_left;
    c.junctions += s.junction;
    if (s.count == 0) return;
    c.tets += s.count;
    c.junction_tets += s.junction ? s.count : 0;
    for (int q = 0; q < 15; ++q) {
        if (!(s.used >> q & 1u)) continue;
        if (q < 4) {
            std::atomic_ref<std::uint8_t>(marks.point[static_cast<std::size_t>(p[static_cast<std::size_t>(q)])]).store(1, std::memory_order_relaxed);
        } else if (q < 10) {
            const std::size_t owner = static_cast<std::size_t>(p[static_cast<std::size_t>(sh.lower[static_cast<std::size_t>(q - 4)])]);
            std::atomic_ref<std::uint8_t>(marks.cut[owner]).fetch_or(static_cast<std::uint8_t>(1u << sh.slot[static_cast<std::size_t>(q - 4)]),
                                                                     std::memory_order_relaxed);
        } else if (q < 14) {
            c.faces.push_back(face_point_of(lay, m, index, p, q - 10));
        } else {
            ++c.centres;
        }
    }
}

std::vector<LayerCount> count_and_mark(const MaterialLayout& lay, Marks& marks) {
    const CubeRange& r = lay.range;
    std::vector<LayerCount> layers(static_cast<std::size_t>(r.hi[2] - r.lo[2]));
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t l = 0; l < r.hi[2] - r.lo[2]; ++l) {
        LayerCount& c = layers[static_cast<std::size_t>(l)];
        for_cubes_in_layer(r, r.lo[2] + l, [&](const bcc::Ivec& m, std::int64_t cx, std::int64_t cy) {
            unsigned mask = 0xFFFu;
            if (lay.tree) {
                const graded3::Cube cube{cx, cy, r.lo[2] + l};
                graded3::Templates t;  // (not zeroed: per cube)
                std::uint16_t material = 0;
                const int k = lay.leaf_templates(cube, t, material);
                c.tets += k, c.templates += k;
                for (int i = 0; i < k; ++i)
                    for (const bcc::Ivec& q : t[static_cast<std::size_t>(i)])
                        std::atomic_ref<std::uint8_t>(marks.point[static_cast<std::size_t>(lay.w.grid.index(q))]).store(1, std::memory_order_relaxed);
                if (!lay.fine_cube(cube, mask)) return;
            }
            const MaterialLayout::CubePoints points = lay.cube_points(m);
            if (const int whole = mask == 0xFFFu ? lay.whole_cube(m, points) : -1; whole >= 0) {
                if (!lay.output[static_cast<std::size_t>(whole)]) return;
                c.tets += 12;
                for (std::size_t k = 0; k < 12; ++k)
                    if (k != 7)  // the corner m + (2, 2, 2) belongs to the cubes above
                        std::atomic_ref<std::uint8_t>(marks.point[static_cast<std::size_t>(points[k])]).store(1, std::memory_order_relaxed);
                return;
            }
            for (int index = 0; index < 12; ++index) {
                if (m[static_cast<std::size_t>(index / 4)] == 0 || !(mask >> index & 1u)) continue;  // no cube below, or a template's
                const std::array<std::int64_t, 4> p = lay.points(points, index);
                count_split(lay, m, index, p, lay.footprint(p, lay.shapes[static_cast<std::size_t>(index)].parity), marks, c);
            }
        });
    }
    return layers;
}

// The position of the cut point between lattice points a and b (window
// indices) of a warped window.
Point3 cut_between(const Window& w, std::int64_t a, std::int64_t b) {
    const bcc::Ivec qa = w.grid.point(a), qb = w.grid.point(b);
    int slot = slot_of(bcc::direction_of(bcc::sub(qb, qa)));
    if (slot < 0) std::swap(a, b), slot = slot_of(bcc::direction_of(bcc::sub(qa, qb)));
    const bcc::Ivec lower = w.grid.point(a);
    return w.cut_position(lower, slot, w.u(a, slot));
}

// Where pass B writes: the vertex ids of every kind, the layers' first
// tetrahedron and first centre.
struct Places {
    Numbering num;
    std::vector<FacePoint> faces;  // sorted by key, unique: face point i has id face_base + i
    std::int64_t face_base = 0, centre_base = 0;
    std::vector<std::int64_t> tet_start, centre_start;
};

// One window's output: the mesh without its boundary and interfaces (found
// by find_boundary on the whole mesh or the merged blocks), the vertices'
// interface flags, the faces on the lattice's cut-off, the keys (blocks) and
// the counts.
struct MaterialOutput {
    TetMesh mesh;
    std::vector<std::uint8_t> on_interface;
    std::vector<CutOff> cut_off;
    std::vector<std::uint64_t> vertex_key, tet_key;
    std::int64_t cut_points = 0;
    LayerCount count;
};

// verify's counts: keys without a claim, tetrahedra outside their key's claim.
struct VerifyCounts {
    std::int64_t uncovered = 0, failures = 0;
};

// verify's check of the tetrahedra [t0, t0 + s.count) of a two-material
// background tetrahedron with lattice points p: each side's tetrahedra
// against its one-region key's claim (generic_bcc_materials.hpp, k = 2).
void verify_sides(const MaterialLayout& lay, const BccKeyClaims& claims, const std::array<std::int64_t, 4>& p, const Split& s,
                  const TetMesh& mesh, std::int64_t t0, VerifyCounts& counts) {
    std::array<bcc::Ivec, 4> q{};
    std::array<int, 4> warp{};
    for (std::size_t k = 0; k < 4; ++k) q[k] = lay.w.grid.point(p[k]), warp[k] = lay.w.warp[static_cast<std::size_t>(p[k])];
    for (std::uint8_t side = 0; side < 2; ++side) {
        std::array<int, 4> sign{};
        for (std::size_t k = 0; k < 4; ++k) sign[k] = s.letter[k] < 0 ? 0 : s.letter[k] == side ? -1 : 1;
        std::optional<BccKeyClaim> claim;
        bool looked = false;
        for (int k = 0; k < s.count; ++k) {
            if (s.side[static_cast<std::size_t>(k)] != side) continue;
            if (!looked) {
                claim = claims.claim(bcc::key_of(q, sign, warp)), looked = true;
                if (!claim) ++counts.uncovered;
            }
            if (!claim) continue;
            std::array<Point3, 4> x{};
            for (std::size_t v = 0; v < 4; ++v) x[v] = mesh.vertices[static_cast<std::size_t>(mesh.tets[static_cast<std::size_t>(t0 + k)][v])];
            if (!key_claim_holds(x, claim->cos2_min, claim->cos2_max)) ++counts.failures;
        }
    }
}

// The faces of output tetrahedron o (bit f: the face without vertex f) on a
// background face with nothing behind it (bit v of `missing`: the face
// without local vertex v).
unsigned faces_on_cut_off(const bcc::OutTet& o, unsigned missing) {
    unsigned faces = 0;
    for (int f = 0; f < 4; ++f)
        for (int v = 0; v < 4; ++v) {
            if (!(missing >> v & 1u)) continue;
            bool on = true;
            for (int j = 0; j < 4; ++j) {
                if (j == f) continue;
                const int q = o[static_cast<std::size_t>(j)];
                on = on && (q < 4 ? q != v : q < 10 ? bcc::tet_edges[static_cast<std::size_t>(q - 4)][0] != v && bcc::tet_edges[static_cast<std::size_t>(q - 4)][1] != v
                                       : q - 10 == v);
            }
            if (on) faces |= 1u << f;
        }
    return faces;
}

// The ids of the 15 local points of split background tetrahedron (index,
// lattice points p) of cube m: vertices, cut points and, for a junction, its
// used face points and its centre (placed here, the centre's id `centre`).
std::array<std::int32_t, 15> point_ids(const MaterialLayout& lay, const Marks& marks, const Places& at, const bcc::Ivec& m, int index,
                                       const std::array<std::int64_t, 4>& p, const Split& s, std::int64_t centre, MaterialOutput& out) {
    const TetShape& sh = lay.shapes[static_cast<std::size_t>(index)];
    std::array<std::int32_t, 15> vid{};
    for (int q = 0; q < 4; ++q) vid[static_cast<std::size_t>(q)] = at.num.id[static_cast<std::size_t>(p[static_cast<std::size_t>(q)])];
    for (int e = 0; e < 6; ++e) {
        const std::size_t owner = static_cast<std::size_t>(p[static_cast<std::size_t>(sh.lower[static_cast<std::size_t>(e)])]);
        const int slot = sh.slot[static_cast<std::size_t>(e)];
        vid[static_cast<std::size_t>(4 + e)] = at.num.cut_id[owner] + slot_count(marks.cut[owner] & ((1u << slot) - 1));
    }
    if (!s.junction) return vid;
    for (int f = 0; f < 4; ++f) {
        const FacePoint key{lay.keys.face(m, index, f), {}};
        const auto it = std::lower_bound(at.faces.begin(), at.faces.end(), key);
        if (it != at.faces.end() && it->key == key.key) vid[static_cast<std::size_t>(10 + f)] = static_cast<std::int32_t>(at.face_base + (it - at.faces.begin()));
    }
    vid[14] = static_cast<std::int32_t>(at.centre_base + centre);
    Point3 c{0, 0, 0};
    for (const std::int64_t q : p) {
        const Point3 x = lay.w.point_position(q);
        c.x += 0.25 * x.x, c.y += 0.25 * x.y, c.z += 0.25 * x.z;
    }
    out.mesh.vertices[static_cast<std::size_t>(vid[14])] = c;
    out.on_interface[static_cast<std::size_t>(vid[14])] = 1;
    if (lay.keyed) out.vertex_key[static_cast<std::size_t>(vid[14])] = lay.keys.centre(m, index);
    return vid;
}

// verify's check of the tetrahedra [t0, t0 + s.count) of a junction
// background tetrahedron (three or four materials) with lattice points p:
// each against the claim of its canonical junction key
// (generic_bcc_materials.hpp, junction_key_of; proofs/bcc_junctions.cert),
// when the claims have junction keys (BccKeyClaims::junction_claim).
void verify_junction(const MaterialLayout& lay, const BccKeyClaims& claims, const std::array<std::int64_t, 4>& p, const Split& s,
                     const TetMesh& mesh, std::int64_t t0, VerifyCounts& counts) {
    if (!claims.junction_claim || s.count == 0) return;
    std::array<bcc::Ivec, 4> q{};
    std::array<int, 4> warp{};
    for (std::size_t k = 0; k < 4; ++k) q[k] = lay.w.grid.point(p[k]), warp[k] = lay.w.warp[static_cast<std::size_t>(p[k])];
    const std::optional<BccKeyClaim> claim = claims.junction_claim(bcc::junction_key_of(q, s.letter, warp));
    if (!claim) {
        ++counts.uncovered;
        return;
    }
    for (int k = 0; k < s.count; ++k) {
        std::array<Point3, 4> x{};
        for (std::size_t v = 0; v < 4; ++v) x[v] = mesh.vertices[static_cast<std::size_t>(mesh.tets[static_cast<std::size_t>(t0 + k)][v])];
        if (!key_claim_holds(x, claim->cos2_min, claim->cos2_max)) ++counts.failures;
    }
}

// Graded meshes, pass B: the output templates of cube c's leaf, written
// from t on with their leaf's material; with claims, each checked against
// the templates' claim (proofs/bcc_graded.cert), when they have it.
void write_templates(const MaterialLayout& lay, const Places& at, const graded3::Cube& c, const BccKeyClaims* verify, std::int64_t& t,
                     MaterialOutput& out, VerifyCounts& counts) {
    graded3::Templates tt;
    std::uint16_t material = 0;
    const int k = lay.leaf_templates(c, tt, material);
    const bool check = verify && verify->template_claim;
    for (int i = 0; i < k; ++i, ++t) {
        std::array<std::int32_t, 4> v{};
        std::array<Point3, 4> x{};
        for (std::size_t j = 0; j < 4; ++j) {
            const bcc::Ivec& q = tt[static_cast<std::size_t>(i)][j];
            v[j] = at.num.id[static_cast<std::size_t>(lay.w.grid.index(q))];
            x[j] = lay.w.lattice_position(q);
        }
        out.mesh.tets[static_cast<std::size_t>(t)] = v;
        out.mesh.region[static_cast<std::size_t>(t)] = lay.field.tag(material);
        if (check && !key_claim_holds(x, verify->template_claim->cos2_min, verify->template_claim->cos2_max)) ++counts.failures;
    }
    if (verify && k > 0 && !verify->template_claim) ++counts.uncovered;
}

// Pass B for layer l of the range: the tetrahedra, their regions (and keys)
// and centres, and the faces on the lattice's cut-off (and, with claims,
// verify's checks).
void write_layer(const MaterialLayout& lay, const Marks& marks, const Places& at, std::int64_t l, const BccKeyClaims* verify,
                 MaterialOutput& out, std::vector<CutOff>& cut_off, VerifyCounts& counts) {
    const Lattice3& L = lay.w.grid.lattice;
    TetMesh& mesh = out.mesh;
    std::int64_t t = at.tet_start[static_cast<std::size_t>(l)], centre = at.centre_start[static_cast<std::size_t>(l)];
    const bcc::OutTet& whole_order = plan(0, 0).stencil.tet[0];  // the all-− stencil's vertex order
    for_cubes_in_layer(lay.range, lay.range.lo[2] + l, [&](const bcc::Ivec& m, std::int64_t cx, std::int64_t cy) {
        unsigned mask = 0xFFFu;
        if (lay.tree) {
            const graded3::Cube cube{cx, cy, lay.range.lo[2] + l};
            write_templates(lay, at, cube, verify, t, out, counts);
            if (!lay.fine_cube(cube, mask)) return;
        }
        const MaterialLayout::CubePoints points = lay.cube_points(m);
        if (const int whole = mask == 0xFFFu ? lay.whole_cube(m, points) : -1; whole >= 0 && !in_lattice_edge(L, m)) {
            if (!lay.output[static_cast<std::size_t>(whole)]) return;
            for (int index = 0; index < 12; ++index, ++t) {
                const std::array<std::int64_t, 4> p = lay.points(points, index);
                mesh.tets[static_cast<std::size_t>(t)] = {at.num.id[static_cast<std::size_t>(p[whole_order[0]])], at.num.id[static_cast<std::size_t>(p[whole_order[1]])],
                                                           at.num.id[static_cast<std::size_t>(p[whole_order[2]])], at.num.id[static_cast<std::size_t>(p[whole_order[3]])]};
                mesh.region[static_cast<std::size_t>(t)] = lay.field.tag(whole);
                if (lay.keyed) out.tet_key[static_cast<std::size_t>(t)] = lay.keys.tet(m, index, 0);
            }
            return;
        }
        for (int index = 0; index < 12; ++index) {
            if (m[static_cast<std::size_t>(index / 4)] == 0 || !(mask >> index & 1u)) continue;
            const TetShape& sh = lay.shapes[static_cast<std::size_t>(index)];
            const std::array<std::int64_t, 4> p = lay.points(points, index);
            const Split s = lay.split(p, sh.parity);
            if (s.count == 0) continue;
            const std::array<std::int32_t, 15> vid = point_ids(lay, marks, at, m, index, p, s, centre, out);
            centre += s.junction;
            const std::int64_t t0 = t;
            unsigned missing = 0;  // bit v: no background tetrahedron across the face without v
            for (int v = 0; v < 4; ++v) missing |= in_lattice(L, bcc::add(m, sh.across[static_cast<std::size_t>(v)])) ? 0u : 1u << v;
            for (int k = 0; k < s.count; ++k, ++t) {
                const bcc::OutTet& o = s.tet[static_cast<std::size_t>(k)];
                mesh.tets[static_cast<std::size_t>(t)] = {vid[o[0]], vid[o[1]], vid[o[2]], vid[o[3]]};
                mesh.region[static_cast<std::size_t>(t)] = lay.field.tag(s.material[static_cast<std::size_t>(k)]);
                if (lay.keyed) out.tet_key[static_cast<std::size_t>(t)] = lay.keys.tet(m, index, k);
                if (!missing) continue;
                if (const unsigned faces = faces_on_cut_off(o, missing)) cut_off.push_back({t, static_cast<std::uint8_t>(faces)});
            }
            if (verify && !s.junction && !s.all_zero) verify_sides(lay, *verify, p, s, mesh, t0, counts);
            if (verify && s.junction) verify_junction(lay, *verify, p, s, mesh, t0, counts);
        }
    });
}

// The vertices of the lattice and cut points (positions, interface flags,
// keys).
void place_points(const MaterialLayout& lay, const Marks& marks, const Numbering& num, MaterialOutput& out) {
    const Window& w = lay.w;
    const Grid& g = w.grid;
    const int planes = g.hi[2] - g.lo[2] + 1;
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z)
        for (std::int64_t p = g.plane_start[static_cast<std::size_t>(z)]; p < g.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
            const std::uint8_t cut = marks.cut[static_cast<std::size_t>(p)];
            if (!marks.point[static_cast<std::size_t>(p)] && !cut) continue;
            const bcc::Ivec q = g.point_in_plane(z, p);
            if (marks.point[static_cast<std::size_t>(p)]) {
                const std::size_t v = static_cast<std::size_t>(num.id[static_cast<std::size_t>(p)]);
                const bool warped = w.warp[static_cast<std::size_t>(p)] != bcc::stay;
                out.mesh.vertices[v] = warped ? w.point_position(p) : w.lattice_position(q);
                out.on_interface[v] = warped;
                if (lay.keyed) out.vertex_key[v] = lay.keys.point(q);
            }
            std::size_t v = static_cast<std::size_t>(num.cut_id[static_cast<std::size_t>(p)]);
            for (int s = 0; s < 7; ++s) {
                if (!(cut >> s & 1u)) continue;
                out.mesh.vertices[v] = w.cut_position(q, s, w.u(p, s)), out.on_interface[v] = 1;
                if (lay.keyed) out.vertex_key[v] = lay.keys.cut(q, s);
                ++v;
            }
        }
}

// The junction face points, each the average of its face's three cut points.
void place_face_points(const MaterialLayout& lay, const Places& at, MaterialOutput& out) {
    for (std::size_t i = 0; i < at.faces.size(); ++i) {
        const Key3& k = at.faces[i].points;
        const Point3 a = cut_between(lay.w, k[0], k[1]), b = cut_between(lay.w, k[1], k[2]), c = cut_between(lay.w, k[2], k[0]);
        const std::size_t v = static_cast<std::size_t>(at.face_base) + i;
        out.mesh.vertices[v] = {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
        out.on_interface[v] = 1;
        if (lay.keyed) out.vertex_key[v] = at.faces[i].key;
    }
}

// The numbering of every vertex kind (mesh3d.hpp's vertex order), from pass A.
Places places_of(const MaterialLayout& lay, const Marks& marks, std::vector<LayerCount>& layers) {
    Places at;
    at.num = number(lay.w.grid, marks);
    for (auto& l : layers) at.faces.insert(at.faces.end(), l.faces.begin(), l.faces.end()), std::vector<FacePoint>().swap(l.faces);
    std::sort(at.faces.begin(), at.faces.end());
    at.faces.erase(std::unique(at.faces.begin(), at.faces.end(), [](const FacePoint& a, const FacePoint& b) { return a.key == b.key; }),
                   at.faces.end());
    at.face_base = at.num.points + at.num.cuts;
    at.centre_base = at.face_base + static_cast<std::int64_t>(at.faces.size());
    at.tet_start.assign(layers.size() + 1, 0), at.centre_start.assign(layers.size() + 1, 0);
    for (std::size_t l = 0; l < layers.size(); ++l)
        at.tet_start[l + 1] = at.tet_start[l] + layers[l].tets, at.centre_start[l + 1] = at.centre_start[l] + layers[l].centres;
    return at;
}

// Number every vertex and write the mesh (pass B).
MaterialOutput assemble(const MaterialLayout& lay, const Marks& marks, std::vector<LayerCount>& layers, std::uint64_t max_memory,
                        const BccKeyClaims* verify) {
    const Places at = places_of(lay, marks, layers);
    const std::int64_t tets = at.tet_start.back(), vertices = at.centre_base + at.centre_start.back();
    if (tets >= INT32_MAX || vertices >= INT32_MAX)
        throw OptionError("spacing", "the 3D mesh would have more than 2^31 tetrahedra or vertices; choose a larger {spacing}");
    const std::uint64_t keyed = lay.keyed ? 8 : 0;
    check_memory(static_cast<std::uint64_t>(tets) * (20 + keyed) + static_cast<std::uint64_t>(vertices) * (25 + keyed), max_memory,
                 "the 3D mesh of " + std::to_string(tets) + " tetrahedra", "about 24 bytes a tetrahedron", "choose a larger {spacing}");
    MaterialOutput out;
    out.cut_points = at.num.cuts;
    out.mesh.vertices.resize(static_cast<std::size_t>(vertices));
    out.mesh.tets.resize(static_cast<std::size_t>(tets));
    out.mesh.region.resize(static_cast<std::size_t>(tets));
    out.on_interface.assign(static_cast<std::size_t>(vertices), 0);
    if (lay.keyed) out.vertex_key.resize(static_cast<std::size_t>(vertices)), out.tet_key.resize(static_cast<std::size_t>(tets));
    place_points(lay, marks, at.num, out);
    place_face_points(lay, at, out);
    std::vector<std::vector<CutOff>> cut_off(layers.size());
    std::vector<VerifyCounts> counts(layers.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t l = 0; l < static_cast<std::int64_t>(layers.size()); ++l)
        write_layer(lay, marks, at, l, verify, out, cut_off[static_cast<std::size_t>(l)], counts[static_cast<std::size_t>(l)]);
    VerifyCounts total;
    for (const VerifyCounts& c : counts) total.uncovered += c.uncovered, total.failures += c.failures;
    if (total.uncovered || total.failures)
        throw std::logic_error("mesh_bcc_materials verify: " + std::to_string(total.uncovered) + " keys without a claim in " +
                               verify->source + ", " + std::to_string(total.failures) + " tetrahedra outside their key's claim");
    for (const auto& c : cut_off) out.cut_off.insert(out.cut_off.end(), c.begin(), c.end());
    for (const LayerCount& l : layers) {
        LayerCount& c = out.count;
        c.tets += l.tets, c.centres += l.centres, c.all_zero += l.all_zero, c.filled += l.filled, c.voids += l.voids;
        c.junctions += l.junctions, c.junction_tets += l.junction_tets, c.templates += l.templates;
    }
    return out;
}

void check_material_options(const BccOptions& options) {
    if (options.face_rule != FaceRule::parity)
        throw InputError("multi-material 3D meshes split their quads by the parity face rule (face_rule parity); the Delaunay "
                         "face rule can make the two sides of an interface disagree");
    check_options(options);
}

// The window's points' materials (the field's, or outside_code), their cut
// points and closest-first warping (`blocked`: with taint, for blocks).
void prepare_materials(const MaterialField3& field, const BccOptions& options, bool keep_background, bool blocked, Window& w,
                       Buffer<std::uint16_t>& material) {
    const std::size_t n = static_cast<std::size_t>(w.grid.count());
    check_memory(static_cast<std::uint64_t>(n) * 12, options.max_memory, "the 3D lattice of " + std::to_string(n) + " points",
                 "about 12 bytes a lattice point", "choose a larger {spacing}");
    material.resize(n);
    w.sign.resize(n);
    const int planes = w.grid.hi[2] - w.grid.lo[2] + 1;
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z)
        for (std::int64_t p = w.grid.plane_start[static_cast<std::size_t>(z)]; p < w.grid.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
            const int m = field.material_at(w.grid.lattice.position(w.grid.point_in_plane(z, p)));
            material[static_cast<std::size_t>(p)] = m == outside_material ? outside_code : static_cast<std::uint16_t>(m);
            w.sign[static_cast<std::size_t>(p)] = -1;  // warp_points sets 0 on the warped points
        }
    find_material_cuts(field, std::span<const std::uint16_t>(material.data(), n), !keep_background, w);
    warp_points(options.alphas, w, blocked);
}

// The output of the cubes `range` of a prepared window (keyed: with global
// keys; verify: every two-material tetrahedron checked).
// (tree: a graded mesh's octree over the whole lattice.)
MaterialOutput emit_materials(const MaterialField3& field, const Window& w, const Buffer<std::uint16_t>& material, const CubeRange& range,
                              const BccOptions& options, bool keep_background, bool keyed, const BccKeyClaims* verify,
                              const graded3::Octree3* tree = nullptr) {
    const std::size_t n = static_cast<std::size_t>(w.grid.count());
    const MaterialLayout lay(w, field, options.fill_claim, std::span<const std::uint16_t>(material.data(), n), keep_background, range, keyed,
                             tree);
    Marks marks{ZeroBuffer<std::uint8_t>(n), ZeroBuffer<std::uint8_t>(n)};
    std::vector<LayerCount> layers = count_and_mark(lay, marks);
    return assemble(lay, marks, layers, options.max_memory, verify);
}

std::vector<std::pair<std::int32_t, std::string>> output_names(const MaterialField3& field, bool keep_background) {
    std::vector<std::pair<std::int32_t, std::string>> names;
    for (int m = keep_background ? 0 : 1; m < field.count(); ++m) names.emplace_back(field.tag(m), field.name(m));
    return names;
}

}  // namespace
}  // namespace uniform3d

namespace uniform3d {
namespace {

// The mesh of the whole lattice, uniform or (graded) on the octree of the
// points' materials (octree3.hpp): the window, the stage's output, the
// domain's faces and the boundary, the counts.
GradedBccMesh whole_materials(const MaterialField3& field, const Lattice3& lattice, const BccOptions& options, bool keep_background,
                              const GradedOptions3* graded) {
    check_material_options(options);
    const ThreadCount threads(options.threads);
    const auto start = std::chrono::steady_clock::now();
    Window w;
    w.grid = Grid::whole(lattice);
    Buffer<std::uint16_t> material;
    prepare_materials(field, options, keep_background, false, w, material);
    GradedBccMesh r;
    MaterialOutput e;
    const CubeRange all{{0, 0, 0}, lattice.cubes};
    if (graded) {
        const std::span<const std::uint16_t> codes(material.data(), static_cast<std::size_t>(w.grid.count()));
        const graded3::Octree3 tree = graded3::build_octree3(w, graded->max_level, graded->buffer, codes, !keep_background);
        e = emit_materials(field, w, material, all, options, keep_background, false, options.verify, &tree);
        r.leaves_per_level = tree.leaves_per_level;
    } else {
        e = emit_materials(field, w, material, all, options, keep_background, false, options.verify);
    }
    if (e.mesh.tets.empty())
        throw InputError("no tetrahedron of any material at spacing " + std::to_string(lattice.spacing) + " (" + field.describe() + ")");
    mark_domain_faces(std::span<const Point3>(e.mesh.vertices.data(), e.mesh.vertices.size()), e.on_interface,
                      field.domain(), lattice.spacing);
    find_boundary(e.mesh, e.on_interface, e.cut_off);
    BccMesh& out = r.bcc;
    out.mesh = std::move(e.mesh);
    out.mesh.region_names = output_names(field, keep_background);
    const LayerCount& c = e.count;
    out.all_zero_left_out = c.all_zero - c.filled, out.all_zero_filled = c.filled, out.all_zero_voids = c.voids;
    out.junction_background_tets = c.junctions, out.junction_tets = c.junction_tets;
    out.cut_points = e.cut_points;
    out.verified = options.verify != nullptr;
    out.lattice_points = lattice.point_count();
    out.background_tets = 12 * lattice.cubes[0] * lattice.cubes[1] * lattice.cubes[2];
    out.warped = w.warp_count;
    r.template_tets = c.templates;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

}  // namespace
}  // namespace uniform3d

BccMesh mesh_bcc_materials(const MaterialField3& field, const Lattice3& lattice, const BccOptions& options, bool keep_background) {
    return uniform3d::whole_materials(field, lattice, options, keep_background, nullptr).bcc;
}

GradedBccMesh mesh_bcc_materials_graded(const MaterialField3& field, const Lattice3& lattice, const BccOptions& options,
                                        bool keep_background, const GradedOptions3& graded) {
    graded3::check_graded_options(graded);
    return uniform3d::whole_materials(field, lattice, options, keep_background, &graded);
}

TetBlock mesh_bcc_materials_block(const MaterialField3& field, const Lattice3& lattice, const BccOptions& options, bool keep_background,
                                  const CubeRange& block) {
    using namespace uniform3d;
    check_material_options(options);
    check_block(lattice, block, "mesh_bcc_materials_block");
    const ThreadCount threads(options.threads);
    Buffer<std::uint16_t> material;
    const Window w = block_window(lattice, block, [&](Window& win) { prepare_materials(field, options, keep_background, true, win, material); });
    MaterialOutput e = emit_materials(field, w, material, block, options, keep_background, true, nullptr);
    mark_domain_faces(std::span<const Point3>(e.mesh.vertices.data(), e.mesh.vertices.size()), e.on_interface,
                      field.domain(), lattice.spacing);
    TetBlock b = make_block(w, block, options, std::move(e.vertex_key), e.mesh.vertices, std::move(e.on_interface), e.mesh.tets,
                            std::move(e.tet_key), e.cut_off);
    b.region.assign(e.mesh.region.begin(), e.mesh.region.end());
    b.region_names = output_names(field, keep_background);
    const LayerCount& c = e.count;
    b.all_zero_left_out = c.all_zero - c.filled, b.all_zero_filled = c.filled, b.all_zero_voids = c.voids;
    b.junction_background_tets = c.junctions, b.junction_tets = c.junction_tets;
    return b;
}

}  // namespace warpmesh
