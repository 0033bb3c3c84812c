// materials3.cpp — the multi-material 3D mesher (mesh3d.hpp:
// mesh_bcc_materials): every lattice point's material, the cut points
// between materials, closest-first warping (warp3.cpp, unchanged: a cut
// edge is one whose ends' materials differ), then every background
// tetrahedron split by generic_bcc_materials.hpp's rule, in two passes over
// the cube layers as tets3.cpp does (count and mark, then number and write),
// and the boundary and interfaces from the faces whose vertices all lie on
// interfaces.
#include <algorithm>
#include <atomic>
#include <optional>
#include <chrono>
#include <stdexcept>
#include <tuple>

#include "uniform3d.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"  // key_of
#include "warpmesh/mesh3d/generic_bcc_materials.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {
namespace uniform3d {
namespace {

using Key3 = std::array<std::int64_t, 3>;


// The split of one background tetrahedron: output tetrahedra over its 15
// local points (generic_bcc_materials.hpp) and their material codes.
struct Split {
    int count = 0;
    std::array<bcc::OutTet, 24> tet{};
    std::array<std::uint16_t, 24> material{};
    std::array<std::uint8_t, 24> side{};  // 0, 1: a two-material side's letter; junction_side; fill_side
    std::array<int, 4> letter{};
    bool all_zero = false, junction = false, void_left = false;
};
inline constexpr std::uint8_t junction_side = 2, fill_side = 3;
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

struct MaterialLayout {
    const Window& w;
    const MaterialField3& field;
    std::optional<BccKeyClaim> fill;   // all-zero background tetrahedra meeting it are output
    std::span<const std::uint16_t> mat;
    std::vector<std::uint8_t> output;  // per material code: output it
    bool merge_outside = false;        // the background dropped: it and the outside are one (no cut between them)
    const std::array<TetShape, 12>& shapes = tet_shapes();
    std::int64_t plane_pair = 0;

    MaterialLayout(const Window& win, const MaterialField3& f, const std::optional<BccKeyClaim>& fill_claim,
                   std::span<const std::uint16_t> material, int count, bool keep_background)
        : w(win), field(f), fill(fill_claim), mat(material), output(65536, 0), merge_outside(!keep_background) {
        plane_pair = win.grid.corner_w * win.grid.corner_h + win.grid.centre_w * win.grid.centre_h;
        for (int m = keep_background ? 0 : 1; m < count; ++m) output[static_cast<std::size_t>(m)] = 1;
    }
    // The window index of the point in neighbourhood slot k of cube m (TetShape::slot_in_cube).
    std::int64_t point_at(const bcc::Ivec& m, int k) const {
        if (k < 8) return w.grid.index(m) + (k & 1) + ((k >> 1) & 1) * w.grid.corner_w + (k >> 2) * plane_pair;
        const std::int64_t centre = w.grid.index(bcc::add(m, {1, 1, 1}));
        return k == 8 ? centre : k == 9 ? centre - 1 : k == 10 ? centre - w.grid.centre_w : centre - plane_pair;
    }
    std::array<std::int64_t, 4> points(const bcc::Ivec& m, int index) const {
        std::array<std::int64_t, 4> p{};
        for (std::size_t k = 0; k < 4; ++k) p[k] = point_at(m, shapes[static_cast<std::size_t>(index)].slot_in_cube[k]);
        return p;
    }
    void push(Split& s, const bcc::OutTet& t, std::uint16_t material, std::uint8_t side) const {
        if (!output[material]) return;
        s.tet[static_cast<std::size_t>(s.count)] = t;
        s.side[static_cast<std::size_t>(s.count)] = side;
        s.material[static_cast<std::size_t>(s.count++)] = material;
    }
    Split split(const std::array<std::int64_t, 4>& p, int parity) const;
    // An all-zero background tetrahedron's material (mesh3d.hpp): the
    // material at its centroid if it is output and the warped tetrahedron
    // meets the fill claim with a margin; -1 if that material is not output
    // (left out, as it would be anyway); void_fill if it is but the claim
    // fails (left out: a void inside the materials).
    int fill_material(const std::array<std::int64_t, 4>& p) const;
    // A cube whose 12 background tetrahedra all exist and whose 12 points
    // (TetShape::slot_in_cube) are unwarped and of one material: that
    // material's code (its tetrahedra are whole), else -1.
    int whole_cube(const bcc::Ivec& m) const {
        if (m[0] == 0 || m[1] == 0 || m[2] == 0) return -1;
        int code = -1;
        for (int k = 0; k < 12; ++k) {
            const std::size_t p = static_cast<std::size_t>(point_at(m, k));
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

Split MaterialLayout::split(const std::array<std::int64_t, 4>& p, int parity) const {
    std::array<std::uint16_t, 4> m{};
    std::array<bool, 4> warped{};
    for (std::size_t k = 0; k < 4; ++k) {
        m[k] = mat[static_cast<std::size_t>(p[k])];
        if (merge_outside && m[k] == outside_code) m[k] = 0;
        warped[k] = w.warp[static_cast<std::size_t>(p[k])] != bcc::stay;
    }
    const std::array<int, 4> letter = bcc::letters_of(m, warped);
    const int k = bcc::letter_count(letter);
    Split s;
    s.letter = letter;
    std::array<std::uint16_t, 4> material_of{};
    for (std::size_t i = 0; i < 4; ++i)
        if (letter[i] >= 0) material_of[static_cast<std::size_t>(letter[i])] = m[i];
    if (k == 0) {
        s.all_zero = true;
        const int f = fill_material(p);
        if (f >= 0) push(s, bcc::OutTet{0, 1, 2, 3}, static_cast<std::uint16_t>(f), fill_side);
        s.void_left = f == void_fill;
        return s;
    }
    if (k >= 3) {
        int code = 0;
        for (int i = 3; i >= 0; --i) code = code * 5 + letter[static_cast<std::size_t>(i)] + 1;
        const bcc::MaterialStencil& st = junction_table()[static_cast<std::size_t>(code * 2 + parity)];
        s.junction = true;
        for (int t = 0; t < st.count; ++t)
            push(s, st.tet[static_cast<std::size_t>(t)].tet, material_of[static_cast<std::size_t>(st.tet[static_cast<std::size_t>(t)].letter)], junction_side);
        return s;
    }
    // One or two letters: the one-region stencil of each side (code = Σ (sign + 1) 3^i).
    for (int side = 0; side < k; ++side) {
        int code = 0;
        for (int i = 3; i >= 0; --i) {
            const int l = letter[static_cast<std::size_t>(i)];
            code = code * 3 + (l < 0 ? 1 : l == side ? 0 : 2);
        }
        const bcc::Stencil& st = plan(code, parity).stencil;
        for (int t = 0; t < st.count; ++t) push(s, st.tet[static_cast<std::size_t>(t)], material_of[static_cast<std::size_t>(side)], static_cast<std::uint8_t>(side));
    }
    return s;
}

template <class Body>
void for_cubes_in_layer(const Lattice3& L, std::int64_t cz, Body&& body) {
    for (std::int64_t cy = 0; cy < L.cubes[1]; ++cy)
        for (std::int64_t cx = 0; cx < L.cubes[0]; ++cx)
            body(bcc::Ivec{static_cast<int>(2 * cx), static_cast<int>(2 * cy), static_cast<int>(2 * cz)});
}

// Whether cube m touches the lattice's cut-off (its tetrahedra may have
// faces there: the general path records them).
bool in_lattice_edge(const Lattice3& L, const bcc::Ivec& m) {
    for (std::size_t a = 0; a < 3; ++a)
        if (m[a] < 4 || m[a] >= 2 * L.cubes[a] - 4) return true;
    return false;
}

// A face point's name: its face's three lattice points (window indices), sorted.
Key3 face_key(const std::array<std::int64_t, 4>& p, int f) {
    Key3 k{};
    for (int i = 0, n = 0; i < 4; ++i)
        if (i != f) k[static_cast<std::size_t>(n++)] = p[static_cast<std::size_t>(i)];
    std::sort(k.begin(), k.end());
    return k;
}

// Pass A's per-layer results.
struct LayerCount {
    std::int64_t tets = 0, centres = 0, all_zero = 0, filled = 0, voids = 0, junctions = 0, junction_tets = 0;
    std::vector<Key3> faces;  // face points used
};

std::vector<LayerCount> count_and_mark(const MaterialLayout& lay, Marks& marks) {
    const Lattice3& L = lay.w.grid.lattice;
    std::vector<LayerCount> layers(static_cast<std::size_t>(L.cubes[2]));
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t cz = 0; cz < L.cubes[2]; ++cz) {
        LayerCount& c = layers[static_cast<std::size_t>(cz)];
        for_cubes_in_layer(L, cz, [&](const bcc::Ivec& m) {
            if (const int whole = lay.whole_cube(m); whole >= 0) {
                if (!lay.output[static_cast<std::size_t>(whole)]) return;
                c.tets += 12;
                for (int k = 0; k < 12; ++k)
                    if (k != 7)  // the corner m + (2, 2, 2) belongs to the cubes above
                        std::atomic_ref<std::uint8_t>(marks.point[static_cast<std::size_t>(lay.point_at(m, k))]).store(1, std::memory_order_relaxed);
                return;
            }
            for (int index = 0; index < 12; ++index) {
                if (m[static_cast<std::size_t>(index / 4)] == 0) continue;  // the cube below does not exist
                const TetShape& sh = lay.shapes[static_cast<std::size_t>(index)];
                const std::array<std::int64_t, 4> p = lay.points(m, index);
                const Split s = lay.split(p, sh.parity);
                c.all_zero += s.all_zero;
                c.filled += s.all_zero && s.count > 0;
                c.voids += s.void_left;
                c.junctions += s.junction;
                if (s.count == 0) continue;
                c.tets += s.count;
                c.junction_tets += s.junction ? s.count : 0;
                unsigned used = 0;
                for (int t = 0; t < s.count; ++t)
                    for (const std::uint8_t q : s.tet[static_cast<std::size_t>(t)]) used |= 1u << q;
                for (int q = 0; q < 15; ++q) {
                    if (!(used >> q & 1u)) continue;
                    if (q < 4) {
                        std::atomic_ref<std::uint8_t>(marks.point[static_cast<std::size_t>(p[static_cast<std::size_t>(q)])]).store(1, std::memory_order_relaxed);
                    } else if (q < 10) {
                        const std::size_t owner = static_cast<std::size_t>(p[static_cast<std::size_t>(sh.lower[static_cast<std::size_t>(q - 4)])]);
                        std::atomic_ref<std::uint8_t>(marks.cut[owner]).fetch_or(static_cast<std::uint8_t>(1u << sh.slot[static_cast<std::size_t>(q - 4)]),
                                                                                 std::memory_order_relaxed);
                    } else if (q < 14) {
                        c.faces.push_back(face_key(p, q - 10));
                    } else {
                        ++c.centres;
                    }
                }
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
    std::vector<Key3> faces;  // sorted, unique: face point i has id face_base + i
    std::int64_t face_base = 0, centre_base = 0;
    std::vector<std::int64_t> tet_start, centre_start;
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

// Pass B for one layer: the tetrahedra, their regions and centres, and the
// faces on the lattice's cut-off (and, with claims, verify's checks).
void write_layer(const MaterialLayout& lay, const MaterialField3& field, const Marks& marks, const Places& at, std::int64_t cz,
                 const BccKeyClaims* verify, TetMesh& mesh, std::vector<std::uint8_t>& on_interface, std::vector<CutOff>& cut_off,
                 VerifyCounts& counts) {
    const Window& w = lay.w;
    const Lattice3& L = w.grid.lattice;
    std::int64_t t = at.tet_start[static_cast<std::size_t>(cz)], centre = at.centre_start[static_cast<std::size_t>(cz)];
    const bcc::OutTet& whole_order = plan(0, 0).stencil.tet[0];  // the all-− stencil's vertex order
    for_cubes_in_layer(L, cz, [&](const bcc::Ivec& m) {
        if (const int whole = lay.whole_cube(m); whole >= 0 && !in_lattice_edge(L, m)) {
            if (!lay.output[static_cast<std::size_t>(whole)]) return;
            for (int index = 0; index < 12; ++index, ++t) {
                const std::array<std::int64_t, 4> p = lay.points(m, index);
                mesh.tets[static_cast<std::size_t>(t)] = {at.num.id[static_cast<std::size_t>(p[whole_order[0]])], at.num.id[static_cast<std::size_t>(p[whole_order[1]])],
                                                           at.num.id[static_cast<std::size_t>(p[whole_order[2]])], at.num.id[static_cast<std::size_t>(p[whole_order[3]])]};
                mesh.region[static_cast<std::size_t>(t)] = field.tag(whole);
            }
            return;
        }
        for (int index = 0; index < 12; ++index) {
            if (m[static_cast<std::size_t>(index / 4)] == 0) continue;
            const TetShape& sh = lay.shapes[static_cast<std::size_t>(index)];
            const std::array<std::int64_t, 4> p = lay.points(m, index);
            const Split s = lay.split(p, sh.parity);
            if (s.count == 0) continue;
            std::array<std::int32_t, 15> vid{};
            for (int q = 0; q < 4; ++q) vid[static_cast<std::size_t>(q)] = at.num.id[static_cast<std::size_t>(p[static_cast<std::size_t>(q)])];
            for (int e = 0; e < 6; ++e) {
                const std::size_t owner = static_cast<std::size_t>(p[static_cast<std::size_t>(sh.lower[static_cast<std::size_t>(e)])]);
                const int slot = sh.slot[static_cast<std::size_t>(e)];
                vid[static_cast<std::size_t>(4 + e)] = at.num.cut_id[owner] + slot_count(marks.cut[owner] & ((1u << slot) - 1));
            }
            if (s.junction) {
                for (int f = 0; f < 4; ++f) {
                    const auto it = std::lower_bound(at.faces.begin(), at.faces.end(), face_key(p, f));
                    if (it != at.faces.end() && *it == face_key(p, f))
                        vid[static_cast<std::size_t>(10 + f)] = static_cast<std::int32_t>(at.face_base + (it - at.faces.begin()));
                }
                vid[14] = static_cast<std::int32_t>(at.centre_base + centre);
                Point3 c{0, 0, 0};
                for (const std::int64_t q : p) {
                    const Point3 x = w.point_position(q);
                    c.x += 0.25 * x.x, c.y += 0.25 * x.y, c.z += 0.25 * x.z;
                }
                mesh.vertices[static_cast<std::size_t>(vid[14])] = c;
                on_interface[static_cast<std::size_t>(vid[14])] = 1;
                ++centre;
            }
            const std::int64_t t0 = t;
            unsigned missing = 0;  // bit v: no background tetrahedron across the face without v
            for (int v = 0; v < 4; ++v) missing |= in_lattice(L, bcc::add(m, sh.across[static_cast<std::size_t>(v)])) ? 0u : 1u << v;
            for (int k = 0; k < s.count; ++k, ++t) {
                const bcc::OutTet& o = s.tet[static_cast<std::size_t>(k)];
                mesh.tets[static_cast<std::size_t>(t)] = {vid[o[0]], vid[o[1]], vid[o[2]], vid[o[3]]};
                mesh.region[static_cast<std::size_t>(t)] = field.tag(s.material[static_cast<std::size_t>(k)]);
                if (!missing) continue;
                unsigned faces = 0;  // its faces on a background face v with nothing behind
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
                if (faces) cut_off.push_back({t, static_cast<std::uint8_t>(faces)});
            }
            if (verify && !s.junction && !s.all_zero) verify_sides(lay, *verify, p, s, mesh, t0, counts);
            if (verify && s.junction) verify_junction(lay, *verify, p, s, mesh, t0, counts);
        }
    });
}

// The vertices of the lattice and cut points (positions, interface flags).
void place_points(const Window& w, const Marks& marks, const Numbering& num, TetMesh& mesh, std::vector<std::uint8_t>& on_interface) {
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
                mesh.vertices[v] = warped ? w.point_position(p) : w.lattice_position(q);
                on_interface[v] = warped;
            }
            std::size_t v = static_cast<std::size_t>(num.cut_id[static_cast<std::size_t>(p)]);
            for (int s = 0; s < 7; ++s)
                if (cut >> s & 1u) mesh.vertices[v] = w.cut_position(q, s, w.u(p, s)), on_interface[v++] = 1;
        }
}

struct FaceRef {
    std::array<std::int32_t, 3> sorted;
    std::int64_t tet;
    int opposite;
    bool operator<(const FaceRef& o) const { return std::tie(sorted, tet, opposite) < std::tie(o.sorted, o.tet, o.opposite); }
};

// The boundary and the interfaces: the faces with three interface vertices
// and those on the cut-off, matched by sorting (mesh3d.hpp).
void find_faces(TetMesh& mesh, std::span<const std::uint8_t> on, std::span<const CutOff> cut_off) {
    std::vector<FaceRef> faces;
    std::vector<std::uint8_t> off_faces;  // per cut_off entry: matched below
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        const auto& tet = mesh.tets[t];
        for (int v = 0; v < 4; ++v) {
            const auto& f = outward_face[static_cast<std::size_t>(v)];
            std::array<std::int32_t, 3> s{tet[static_cast<std::size_t>(f[0])], tet[static_cast<std::size_t>(f[1])], tet[static_cast<std::size_t>(f[2])]};
            if (!(on[static_cast<std::size_t>(s[0])] && on[static_cast<std::size_t>(s[1])] && on[static_cast<std::size_t>(s[2])])) continue;
            std::sort(s.begin(), s.end());
            faces.push_back({s, static_cast<std::int64_t>(t), v});
        }
    }
    for (const CutOff& c : cut_off)
        for (int v = 0; v < 4; ++v) {
            if (!(c.second >> v & 1u)) continue;
            const auto& tet = mesh.tets[static_cast<std::size_t>(c.first)];
            const auto& f = outward_face[static_cast<std::size_t>(v)];
            std::array<std::int32_t, 3> s{tet[static_cast<std::size_t>(f[0])], tet[static_cast<std::size_t>(f[1])], tet[static_cast<std::size_t>(f[2])]};
            std::sort(s.begin(), s.end());
            faces.push_back({s, c.first, v});
        }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end(), [](const FaceRef& a, const FaceRef& b) { return a.sorted == b.sorted && a.tet == b.tet; }),
                faces.end());
    const auto outward = [&](const FaceRef& r) {
        const auto& tet = mesh.tets[static_cast<std::size_t>(r.tet)];
        const auto& f = outward_face[static_cast<std::size_t>(r.opposite)];
        return std::array<std::int32_t, 3>{tet[static_cast<std::size_t>(f[0])], tet[static_cast<std::size_t>(f[1])], tet[static_cast<std::size_t>(f[2])]};
    };
    for (std::size_t i = 0; i < faces.size();) {
        std::size_t j = i + 1;
        while (j < faces.size() && faces[j].sorted == faces[i].sorted) ++j;
        if (j - i > 2) throw std::logic_error("mesh_bcc_materials: a face in three tetrahedra");
        const FaceRef& a = faces[i];
        if (j - i == 1) {
            const bool level = on[static_cast<std::size_t>(a.sorted[0])] && on[static_cast<std::size_t>(a.sorted[1])] && on[static_cast<std::size_t>(a.sorted[2])];
            mesh.boundary.push_back(outward(a));
            mesh.boundary_tag.push_back(level ? boundary_level_set : boundary_domain);
        } else if (mesh.region[static_cast<std::size_t>(a.tet)] != mesh.region[static_cast<std::size_t>(faces[i + 1].tet)]) {
            mesh.interfaces.push_back(outward(a));  // from a's tetrahedron (the first in order) into the other
            mesh.interface_regions.push_back({mesh.region[static_cast<std::size_t>(a.tet)], mesh.region[static_cast<std::size_t>(faces[i + 1].tet)]});
        }
        i = j;
    }
}

// Number every vertex and write the mesh (pass B).
TetMesh assemble(const MaterialLayout& lay, const MaterialField3& field, const Marks& marks, std::vector<LayerCount>& layers,
                 const BccOptions& options, std::vector<std::uint8_t>& on_interface, std::int64_t& cut_points) {
    const std::uint64_t max_memory = options.max_memory;
    const Window& w = lay.w;
    Places at;
    at.num = number(w.grid, marks);
    cut_points = at.num.cuts;
    for (auto& l : layers) at.faces.insert(at.faces.end(), l.faces.begin(), l.faces.end()), std::vector<Key3>().swap(l.faces);
    std::sort(at.faces.begin(), at.faces.end());
    at.faces.erase(std::unique(at.faces.begin(), at.faces.end()), at.faces.end());
    at.face_base = at.num.points + at.num.cuts;
    at.centre_base = at.face_base + static_cast<std::int64_t>(at.faces.size());
    at.tet_start.assign(layers.size() + 1, 0), at.centre_start.assign(layers.size() + 1, 0);
    for (std::size_t l = 0; l < layers.size(); ++l)
        at.tet_start[l + 1] = at.tet_start[l] + layers[l].tets, at.centre_start[l + 1] = at.centre_start[l] + layers[l].centres;
    const std::int64_t tets = at.tet_start.back(), vertices = at.centre_base + at.centre_start.back();
    if (tets >= INT32_MAX || vertices >= INT32_MAX)
        throw OptionError("spacing", "the 3D mesh would have more than 2^31 tetrahedra or vertices; choose a larger {spacing}");
    check_memory(static_cast<std::uint64_t>(tets) * 20 + static_cast<std::uint64_t>(vertices) * 25, max_memory,
                 "the 3D mesh of " + std::to_string(tets) + " tetrahedra", "about 24 bytes a tetrahedron", "choose a larger {spacing}");
    TetMesh mesh;
    mesh.vertices.resize(static_cast<std::size_t>(vertices));
    mesh.tets.resize(static_cast<std::size_t>(tets));
    mesh.region.resize(static_cast<std::size_t>(tets));
    on_interface.assign(static_cast<std::size_t>(vertices), 0);
    place_points(w, marks, at.num, mesh, on_interface);
    for (std::size_t i = 0; i < at.faces.size(); ++i) {
        const Key3& k = at.faces[i];
        const Point3 a = cut_between(w, k[0], k[1]), b = cut_between(w, k[1], k[2]), c = cut_between(w, k[2], k[0]);
        mesh.vertices[static_cast<std::size_t>(at.face_base) + i] = {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
        on_interface[static_cast<std::size_t>(at.face_base) + i] = 1;
    }
    std::vector<std::vector<CutOff>> cut_off(layers.size());
    std::vector<VerifyCounts> counts(layers.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t cz = 0; cz < static_cast<std::int64_t>(layers.size()); ++cz)
        write_layer(lay, field, marks, at, cz, options.verify, mesh, on_interface, cut_off[static_cast<std::size_t>(cz)],
                    counts[static_cast<std::size_t>(cz)]);
    VerifyCounts total;
    for (const VerifyCounts& c : counts) total.uncovered += c.uncovered, total.failures += c.failures;
    if (total.uncovered || total.failures)
        throw std::logic_error("mesh_bcc_materials verify: " + std::to_string(total.uncovered) + " keys without a claim in " +
                               options.verify->source + ", " + std::to_string(total.failures) + " tetrahedra outside their key's claim");
    std::vector<CutOff> all;
    for (const auto& c : cut_off) all.insert(all.end(), c.begin(), c.end());
    find_faces(mesh, on_interface, all);
    return mesh;
}

}  // namespace
}  // namespace uniform3d

BccMesh mesh_bcc_materials(const MaterialField3& field, const Lattice3& lattice, const BccOptions& options, bool keep_background) {
    using namespace uniform3d;
    if (options.face_rule != FaceRule::parity)
        throw InputError("multi-material 3D meshes split their quads by the parity face rule (face_rule parity); the Delaunay "
                         "face rule can make the two sides of an interface disagree");
    const auto a = options.alphas;
    if (!(a.long_den > 0 && a.short_den > 0 && a.long_num > 0 && a.short_num > 0 && 2 * a.long_num < a.long_den &&
          2 * a.short_num < a.short_den))
        throw InputError("the alphas must lie in (0, 1/2)");
    const ThreadCount threads(options.threads);
    const auto start = std::chrono::steady_clock::now();
    Window w;
    w.grid = Grid::whole(lattice);
    const std::size_t n = static_cast<std::size_t>(w.grid.count());
    check_memory(static_cast<std::uint64_t>(n) * 12, options.max_memory, "the 3D lattice of " + std::to_string(n) + " points",
                 "about 12 bytes a lattice point", "choose a larger {spacing}");
    Buffer<std::uint16_t> material(n);
    w.sign.resize(n);
    const int planes = w.grid.hi[2] - w.grid.lo[2] + 1;
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z)
        for (std::int64_t p = w.grid.plane_start[static_cast<std::size_t>(z)]; p < w.grid.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
            const int m = field.material_at(w.grid.lattice.position(w.grid.point_in_plane(z, p)));
            material[static_cast<std::size_t>(p)] =
                m == outside_material ? outside_code : static_cast<std::uint16_t>(m);
            w.sign[static_cast<std::size_t>(p)] = -1;  // warp_points sets 0 on the warped points
        }
    find_material_cuts(field, std::span<const std::uint16_t>(material.data(), n), !keep_background, w);
    warp_points(options.alphas, w, false);
    const MaterialLayout lay(w, field, options.fill_claim, std::span<const std::uint16_t>(material.data(), n), field.count(), keep_background);
    Marks marks{ZeroBuffer<std::uint8_t>(n), ZeroBuffer<std::uint8_t>(n)};
    std::vector<LayerCount> layers = count_and_mark(lay, marks);
    BccMesh out;
    for (const LayerCount& l : layers)
        out.all_zero_left_out += l.all_zero - l.filled, out.all_zero_filled += l.filled, out.all_zero_voids += l.voids, out.junction_background_tets += l.junctions, out.junction_tets += l.junction_tets;
    std::vector<std::uint8_t> on_interface;
    out.mesh = assemble(lay, field, marks, layers, options, on_interface, out.cut_points);
    out.verified = options.verify != nullptr;
    if (out.mesh.tets.empty())
        throw InputError("no tetrahedron of any material at spacing " + std::to_string(lattice.spacing) + " (" + field.describe() + ")");
    for (int m = keep_background ? 0 : 1; m < field.count(); ++m) out.mesh.region_names.emplace_back(field.tag(m), field.name(m));
    out.lattice_points = lattice.point_count();
    out.background_tets = 12 * lattice.cubes[0] * lattice.cubes[1] * lattice.cubes[2];
    out.warped = w.warp_count;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace warpmesh
