// stencils3.cpp — stage 5's tables: generic_bcc.hpp's stencils for every
// post-warp sign pattern and parity bit (81 × 2, the parity rule) and for
// every sign pattern and resolved choice of diagonals (81 × 32, any face
// rule: stencil_with), and the 12 background tetrahedra of a cube in their
// local frame.  Computed once; the per-tetrahedron work is then a table
// lookup.
#include "uniform3d.hpp"

namespace warpmesh::uniform3d {
namespace {

// The background faces (bit v: the face without local vertex v) holding
// local point q: a vertex lies on the three faces without another vertex, a
// cut point on the two faces without either end of its edge.
unsigned faces_containing(int q) {
    if (q < 4) return 0xFu & ~(1u << q);
    const auto& e = bcc::tet_edges[static_cast<std::size_t>(q - 4)];
    return 0xFu & ~(1u << e[0]) & ~(1u << e[1]);
}

std::array<int, 4> signs_of(int code) {
    std::array<int, 4> sign{};
    for (int i = 0, c = code; i < 4; ++i, c /= 3) sign[static_cast<std::size_t>(i)] = c % 3 - 1;
    return sign;
}


// The plan of the stencil of `sign` split as `d` says.
Plan make_plan(const std::array<int, 4>& sign, const bcc::Diagonals& d) {
    Plan p;
    int nn = 0, np = 0;
    for (int v : sign) nn += v < 0, np += v > 0;
    p.quads = nn >= 2 && np >= 1;
    p.cyclic = bcc::is_cyclic(sign, d);
    if (p.cyclic) return p;
    p.stencil = bcc::stencil_with(sign, d);
    for (int t = 0; t < p.stencil.count; ++t) {
        const bcc::OutTet& o = p.stencil.tet[static_cast<std::size_t>(t)];
        for (std::uint8_t q : o) p.uses = static_cast<std::uint16_t>(p.uses | 1u << q);
        for (int f = 0; f < 4; ++f) {
            unsigned on = 0xF;
            for (int k = 0; k < 4; ++k)
                if (k != f) on &= faces_containing(o[static_cast<std::size_t>(k)]);
            p.face_on[static_cast<std::size_t>(t)][static_cast<std::size_t>(f)] = static_cast<std::uint8_t>(on);
        }
    }
    return p;
}

std::array<Plan, 81 * 2> make_plans() {
    std::array<Plan, 81 * 2> plans{};
    for (int code = 0; code < 81; ++code)
        for (int parity = 0; parity < 2; ++parity)  // stencil(sign, parity) = stencil_with(sign, parity_diagonals)
            plans[static_cast<std::size_t>(code * 2 + parity)] = make_plan(signs_of(code), bcc::parity_diagonals(signs_of(code), parity));
    return plans;
}

std::vector<Plan> make_diagonal_plans() {
    std::vector<Plan> plans(81 * diagonal_slots);
    for (int code = 0; code < 81; ++code)
        for (int slot = 0; slot < diagonal_slots; ++slot)
            plans[static_cast<std::size_t>(code * diagonal_slots + slot)] =
                make_plan(signs_of(code), bcc::Diagonals{static_cast<unsigned>(slot) >> 1, (slot & 1) != 0});
    return plans;
}

// The lower (in (z, y, x) order) of two points.
bool before(const bcc::Ivec& a, const bcc::Ivec& b) {
    if (a[2] != b[2]) return a[2] < b[2];
    if (a[1] != b[1]) return a[1] < b[1];
    return a[0] < b[0];
}

std::array<TetShape, 12> make_shapes() {
    std::array<TetShape, 12> shapes{};
    for (int index = 0; index < 12; ++index) {
        TetShape& s = shapes[static_cast<std::size_t>(index)];
        s.offset = bcc::background_tet({0, 0, 0}, index);
        s.parity = bcc::tet_parity(s.offset);  // invariant under even translations (generic_bcc.hpp)
        for (int e = 0; e < 6; ++e) {
            const int i = bcc::tet_edges[static_cast<std::size_t>(e)][0], j = bcc::tet_edges[static_cast<std::size_t>(e)][1];
            const bool i_low = before(s.offset[static_cast<std::size_t>(i)], s.offset[static_cast<std::size_t>(j)]);
            const int lo = i_low ? i : j, hi = i_low ? j : i;
            s.lower[static_cast<std::size_t>(e)] = lo;
            s.slot[static_cast<std::size_t>(e)] =
                slot_of(bcc::direction_of(bcc::sub(s.offset[static_cast<std::size_t>(hi)], s.offset[static_cast<std::size_t>(lo)])));
        }
        for (int v = 0; v < 4; ++v) {
            const bcc::Ivec& o = s.offset[static_cast<std::size_t>(v)];
            if (bcc::is_corner(o)) s.slot_in_cube[static_cast<std::size_t>(v)] = o[0] / 2 + o[1] + 2 * o[2];
            else if (o == bcc::Ivec{1, 1, 1}) s.slot_in_cube[static_cast<std::size_t>(v)] = 8;
            else for (int a = 0; a < 3; ++a) if (o[static_cast<std::size_t>(a)] == -1) s.slot_in_cube[static_cast<std::size_t>(v)] = 9 + a;
        }
        for (int v = 0; v < 4; ++v) {  // the face without v holds one long edge: (2, 3) if v < 2, else (0, 1)
            const int x = v < 2 ? 2 : 0, y = x + 1;
            s.across[static_cast<std::size_t>(v)] =
                bcc::sub(bcc::add(s.offset[static_cast<std::size_t>(x)], s.offset[static_cast<std::size_t>(y)]), s.offset[static_cast<std::size_t>(v)]);
        }
    }
    return shapes;
}

}  // namespace

std::span<const Plan> plans() {
    static const std::array<Plan, 81 * 2> all = make_plans();
    return all;
}

const Plan& plan(int code, int parity) { return plans()[static_cast<std::size_t>(code * 2 + parity)]; }

std::span<const Plan> diagonal_plans() {
    static const std::vector<Plan> all = make_diagonal_plans();
    return all;
}

const std::array<TetShape, 12>& tet_shapes() {
    static const std::array<TetShape, 12> shapes = make_shapes();
    return shapes;
}

}  // namespace warpmesh::uniform3d
