// The A15 generic cell of generic_a15.hpp (issue 51), proved in exact
// arithmetic (integer coordinates, quadrupled; rationals for cut points):
// the sites are Cr₃Si's; the 46 cell tetrahedra are positively oriented
// images of their class's reference under lattice symmetries, tile space,
// are Delaunay with no cospherical ties, and have every dihedral angle in
// [arccos(3/5), arccos(1/5)] = [53.130°, 78.463°]; the neighbour tables are
// the tetrahedralization's edges; the class symmetries are exactly the
// references' lattice stabilisers; every stencil is positive in every
// class; the face form is the empty-circle test; and the face rule is
// conforming between neighbours, ties included, with no cyclic prism.
#define BOOST_TEST_MODULE a15_definition
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "warpmesh/mesh3d/generic_a15.hpp"
#include "exact_rational.hpp"

using namespace warpmesh;
using a15::Ivec;
using boost::multiprecision::cpp_rational;
using warpmesh::testing::Q;

namespace {

using Tet = std::array<Ivec, 4>;
using I128 = __int128;

Ivec scale(const Ivec& a, int k) { return {k * a[0], k * a[1], k * a[2]}; }
Ivec shifted(const Ivec& a, const Ivec& m) { return bcc::add(a, scale(m, 4)); }
Tet translated(const Tet& t, const Ivec& m) { return {shifted(t[0], m), shifted(t[1], m), shifted(t[2], m), shifted(t[3], m)}; }

// The cell tetrahedra of the cells m with |m_k| <= reach.
std::vector<Tet> block_tets(int reach) {
    std::vector<Tet> out;
    for (int x = -reach; x <= reach; ++x)
        for (int y = -reach; y <= reach; ++y)
            for (int z = -reach; z <= reach; ++z)
                for (const auto& c : a15::cell_tets) out.push_back(translated(c.v, {x, y, z}));
    return out;
}

I128 det3(const std::array<I128, 3>& a, const std::array<I128, 3>& b, const std::array<I128, 3>& c) {
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}
// det [[p_i − x, |p_i − x|²]] (i = 0..3): its sign tells inside from outside
// of the sphere through p (the side is calibrated on a point known inside).
I128 insphere(const Tet& p, const Ivec& x) {
    std::array<std::array<I128, 4>, 4> m{};
    for (std::size_t i = 0; i < 4; ++i) {
        I128 n = 0;
        for (std::size_t k = 0; k < 3; ++k) {
            m[i][k] = p[i][k] - x[k];
            n += m[i][k] * m[i][k];
        }
        m[i][3] = n;
    }
    I128 d = 0;
    for (std::size_t j = 0; j < 4; ++j) {  // expansion along the last column
        std::array<std::array<I128, 3>, 3> minor{};
        std::size_t r = 0;
        for (std::size_t i = 0; i < 4; ++i) {
            if (i == j) continue;
            minor[r++] = {m[i][0], m[i][1], m[i][2]};
        }
        const I128 cof = det3(minor[0], minor[1], minor[2]) * m[j][3];
        d += ((j + 3) % 2 == 0 ? cof : -cof);
    }
    return d;
}

// The lattice symmetries modulo 4 Z³: signed permutations with shifts in
// {0..3}³ mapping every site to a site of the same type.
std::vector<a15::LatticeOp> lattice_ops() {
    std::vector<a15::LatticeOp> ops;
    std::array<int, 3> perm{1, 2, 3};
    do {
        for (int s = 0; s < 8; ++s)
            for (int t = 0; t < 64; ++t) {
                const a15::LatticeOp g{{(s & 1 ? -1 : 1) * perm[0], (s & 2 ? -1 : 1) * perm[1], (s & 4 ? -1 : 1) * perm[2]},
                                       {t % 4, t / 4 % 4, t / 16}};
                bool ok = true;
                for (int i = 0; i < a15::site_count && ok; ++i) {
                    const int j = a15::site_of(a15::apply(g, a15::sites[static_cast<std::size_t>(i)]));
                    ok = j >= 0 && a15::site_is_a(j) == a15::site_is_a(i);
                }
                if (ok) ops.push_back(g);
            }
    } while (std::next_permutation(perm.begin(), perm.end()));
    return ops;
}

std::set<Ivec> neighbour_set(int s) {
    const auto& n = a15::neighbours[static_cast<std::size_t>(s)];
    return {n.offset.begin(), n.offset.begin() + n.count};
}

}  // namespace

BOOST_AUTO_TEST_CASE(sites_are_those_of_cr3si) {
    // Cr₃Si (β-W, Pm-3n): Si at 2a (0,0,0), (½,½,½); Cr at 6c (¼,0,½),
    // (¾,0,½), (½,¼,0), (½,¾,0), (0,½,¼), (0,½,¾); quadrupled.
    const std::set<Ivec> a{{0, 0, 0}, {2, 2, 2}};
    const std::set<Ivec> b{{1, 0, 2}, {3, 0, 2}, {2, 1, 0}, {2, 3, 0}, {0, 2, 1}, {0, 2, 3}};
    for (int s = 0; s < a15::site_count; ++s) {
        const Ivec& p = a15::sites[static_cast<std::size_t>(s)];
        BOOST_TEST((a15::site_is_a(s) ? a.count(p) : b.count(p)) == 1u);
        const Ivec q = shifted(p, {-3, 2, -1});
        BOOST_TEST(a15::site_of(q) == s);
        BOOST_TEST((a15::cell_of(q) == Ivec{-3, 2, -1}));
    }
    BOOST_TEST(a15::site_of({1, 1, 0}) == -1);
    BOOST_TEST(a15::site_of({-2, -2, -2}) == 1);
}

BOOST_AUTO_TEST_CASE(the_lattice_has_48_symmetries_and_the_tables_use_them) {
    const auto ops = lattice_ops();
    BOOST_TEST(ops.size() == 48u);
    BOOST_TEST(std::count_if(ops.begin(), ops.end(), [](const auto& g) { return a15::det(g) == 1; }) == 24);
    // Each symmetry maps a site's edges onto its image's edges (M⁻¹ back).
    for (const auto& g : ops)
        for (int s = 0; s < a15::site_count; ++s) {
            const int t = a15::site_of(a15::apply(g, a15::sites[static_cast<std::size_t>(s)]));
            std::set<Ivec> back;
            for (const Ivec& d : neighbour_set(t)) back.insert(a15::to_local(g, d));
            BOOST_TEST((back == neighbour_set(s)));
        }
}

BOOST_AUTO_TEST_CASE(cell_tets_are_oriented_images_of_their_references) {
    std::array<int, 3> count{};
    const std::array<std::vector<int>, 3> signature{std::vector<int>{4, 5, 5, 5, 6, 6}, {5, 5, 5, 6, 6, 6}, {4, 4, 6, 6, 6, 6}};
    for (int c = 0; c < a15::class_count; ++c) BOOST_TEST(bcc::orientation(a15::reference_tets[static_cast<std::size_t>(c)]) > 0);
    for (const auto& t : a15::cell_tets) {
        ++count[static_cast<std::size_t>(t.cls)];
        const auto& ref = a15::reference_tets[static_cast<std::size_t>(t.cls)];
        for (std::size_t i = 0; i < 4; ++i) {
            BOOST_TEST((a15::apply(t.op, ref[i]) == t.v[i]));
            BOOST_TEST(a15::site_is_a(a15::site_of(t.v[i])) == a15::site_is_a(a15::site_of(ref[i])));
        }
        BOOST_TEST(bcc::orientation(t.v) * a15::det(t.op) > 0);
        std::vector<int> len;
        for (const auto& e : bcc::tet_edges) len.push_back(a15::norm2(bcc::sub(t.v[static_cast<std::size_t>(e[1])], t.v[static_cast<std::size_t>(e[0])])));
        std::sort(len.begin(), len.end());
        BOOST_TEST(len == signature[static_cast<std::size_t>(t.cls)], boost::test_tools::per_element());
    }
    for (int c = 0; c < a15::class_count; ++c) BOOST_TEST(count[static_cast<std::size_t>(c)] == a15::class_size[static_cast<std::size_t>(c)]);
    // Classes 0 and 2 need proper symmetries only; class 1 half improper.
    int improper = 0;
    for (const auto& t : a15::cell_tets) improper += a15::det(t.op) < 0 ? (t.cls == 1 ? 1 : 100) : 0;
    BOOST_TEST(improper == 8);
}

BOOST_AUTO_TEST_CASE(cell_tets_tile_space) {
    // Volumes: Σ 6·vol = 6 · 4³.  Ownership: 4 × the centroid lies in the
    // cell [0, 16)³.  Faces: each face of a cell tetrahedron is a face of
    // exactly one other tetrahedron of the surrounding block (a translate
    // where it crosses the cell), lying on the other side of it.  A closed,
    // positively oriented complex of total volume the cell's covers the
    // torus R³/4Z³ once: a tiling.
    long vol6 = 0;
    for (const auto& t : a15::cell_tets) {
        vol6 += std::labs(bcc::orientation(t.v));
        for (std::size_t k = 0; k < 3; ++k) {
            const int c4 = t.v[0][k] + t.v[1][k] + t.v[2][k] + t.v[3][k];
            BOOST_TEST((c4 >= 0 && c4 < 16));
        }
    }
    BOOST_TEST(vol6 == 6 * 64);
    const auto block = block_tets(1);
    std::map<std::set<Ivec>, std::vector<std::size_t>> faces;
    for (std::size_t i = 0; i < block.size(); ++i)
        for (std::size_t f = 0; f < 4; ++f) {
            std::set<Ivec> face;
            for (std::size_t j = 0; j < 4; ++j)
                if (j != f) face.insert(block[i][j]);
            faces[face].push_back(i * 4 + f);
        }
    int checked = 0;
    for (std::size_t i = 0; i < a15::cell_tets.size(); ++i) {
        const Tet& t = block[13 * a15::cell_tets.size() + i];  // cell (0, 0, 0)
        BOOST_TEST((t == a15::cell_tets[i].v));
        for (std::size_t f = 0; f < 4; ++f) {
            std::set<Ivec> face;
            for (std::size_t j = 0; j < 4; ++j)
                if (j != f) face.insert(t[j]);
            const auto& owners = faces[face];
            BOOST_TEST_REQUIRE(owners.size() == 2u);
            const std::size_t o = owners[0] / 4 == 13 * a15::cell_tets.size() + i ? owners[1] : owners[0];
            // The two apexes lie strictly on opposite sides of the face.
            const Tet& u = block[o / 4];
            const Ivec apex_t = t[f], apex_u = u[o % 4];
            const std::vector<Ivec> fv(face.begin(), face.end());
            const long st = bcc::orientation({fv[0], fv[1], fv[2], apex_t});
            const long su = bcc::orientation({fv[0], fv[1], fv[2], apex_u});
            BOOST_TEST(st * su < 0);
            ++checked;
        }
    }
    BOOST_TEST(checked == 184);
}

BOOST_AUTO_TEST_CASE(tetrahedralization_is_delaunay_without_cospherical_ties) {
    // Every lattice point of the cells [-2, 2]³ other than a tetrahedron's
    // vertices lies strictly outside its circumsphere (coordinates ×4 again,
    // so that the centroid, strictly inside the sphere, is integral and
    // calibrates the sign).  Strictness for all of them: no five sites are
    // cospherical, so the Delaunay tetrahedralization is unique.  The block
    // holds every sphere (checked below).
    std::vector<Ivec> points;
    for (int x = -2; x <= 2; ++x)
        for (int y = -2; y <= 2; ++y)
            for (int z = -2; z <= 2; ++z)
                for (const Ivec& s : a15::sites) points.push_back(scale(shifted(s, {x, y, z}), 4));
    int outside = 0;
    for (const auto& c : a15::cell_tets) {
        const Tet t{scale(c.v[0], 4), scale(c.v[1], 4), scale(c.v[2], 4), scale(c.v[3], 4)};
        const Ivec centroid = bcc::add(bcc::add(c.v[0], c.v[1]), bcc::add(c.v[2], c.v[3]));
        const I128 inside = insphere(t, centroid);
        BOOST_TEST_REQUIRE((inside != 0));
        for (const Ivec& p : points) {
            if (std::find(t.begin(), t.end(), p) != t.end()) continue;
            const I128 s = insphere(t, p);
            BOOST_TEST(((s > 0) != (inside > 0) && s != 0));
            ++outside;
        }
        // The circumsphere lies strictly inside the block's box (-8, 12)³
        // (quadrupled), so no lattice point outside the block is in it:
        // centre c by Cramer's rule on 2 (p_i − p_0) · c = |p_i|² − |p_0|²,
        // radius² |c − p_0|², all exact.
        std::array<std::array<I128, 3>, 3> A{};
        std::array<I128, 3> b{};
        for (std::size_t i = 1; i < 4; ++i) {
            for (std::size_t k = 0; k < 3; ++k) A[i - 1][k] = 2 * (c.v[i][k] - c.v[0][k]);
            b[i - 1] = a15::norm2(c.v[i]) - a15::norm2(c.v[0]);
        }
        const I128 D = det3(A[0], A[1], A[2]);
        std::array<cpp_rational, 3> centre{};
        for (std::size_t k = 0; k < 3; ++k) {
            auto Ak = A;
            for (std::size_t i = 0; i < 3; ++i) Ak[i][k] = b[i];
            centre[k] = cpp_rational(static_cast<long long>(det3(Ak[0], Ak[1], Ak[2]))) / static_cast<long long>(D);
        }
        cpp_rational R2 = 0;
        for (std::size_t k = 0; k < 3; ++k) R2 += (centre[k] - c.v[0][k]) * (centre[k] - c.v[0][k]);
        for (std::size_t k = 0; k < 3; ++k) {
            BOOST_TEST((centre[k] > -8 && (centre[k] + 8) * (centre[k] + 8) > R2));
            BOOST_TEST((centre[k] < 12 && (12 - centre[k]) * (12 - centre[k]) > R2));
        }
    }
    BOOST_TEST(outside == 46 * (1000 - 4));
}

BOOST_AUTO_TEST_CASE(neighbours_are_the_edges_of_the_tetrahedralization) {
    // The edges at each site of cell 0 (every tetrahedron at it lies in the
    // block of cells [-1, 1]³) are exactly its `neighbours`: 12 mixed at an
    // A site, 2 chain + 4 mixed + 8 wide at a B site, ordered by length then
    // lexicographically; mixed iff the ends differ in type.
    const auto block = block_tets(1);
    for (int s = 0; s < a15::site_count; ++s) {
        const Ivec& p = a15::sites[static_cast<std::size_t>(s)];
        std::set<Ivec> edges;
        for (const Tet& t : block)
            if (std::find(t.begin(), t.end(), p) != t.end())
                for (const Ivec& q : t)
                    if (q != p) edges.insert(bcc::sub(q, p));
        BOOST_TEST((edges == neighbour_set(s)));
        const auto& n = a15::neighbours[static_cast<std::size_t>(s)];
        BOOST_TEST(n.count == (a15::site_is_a(s) ? 12 : 14));
        std::array<int, 3> per_class{};
        for (int i = 0; i < n.count; ++i) {
            const Ivec& d = n.offset[static_cast<std::size_t>(i)];
            const int other = a15::site_of(bcc::add(p, d));
            ++per_class[static_cast<std::size_t>(a15::edge_class(d))];
            BOOST_TEST((a15::edge_class(d) == a15::EdgeClass::mixed) == (a15::site_is_a(s) != a15::site_is_a(other)));
            BOOST_TEST(a15::direction_of(s, d) == i);
            if (i > 0) {
                const Ivec& e = n.offset[static_cast<std::size_t>(i - 1)];
                BOOST_TEST((std::pair{a15::norm2(e), e} < std::pair{a15::norm2(d), d}));
            }
        }
        const std::array<int, 3> expect = a15::site_is_a(s) ? std::array<int, 3>{0, 12, 0} : std::array<int, 3>{2, 4, 8};
        BOOST_TEST(per_class == expect, boost::test_tools::per_element());
    }
}

BOOST_AUTO_TEST_CASE(dihedral_angles_are_acute_within_53_13_and_78_46_degrees) {
    // θ >= arccos(3/5) <=> n_c·n_d <= 0 or (n_c·n_d)² <= 9/25 |n_c|²|n_d|²,
    // θ <= arccos(1/5) <=> n_c·n_d >= 0 or (n_c·n_d)² >= 1/25 |n_c|²|n_d|²
    // (generic_bcc.hpp, "Angle forms"); acute <=> n_c·n_d > 0.  Both bounds
    // are attained.
    bool lo = false, hi = false;
    for (const auto& c : a15::cell_tets) {
        std::array<bcc::Vec<long long>, 4> p{};
        for (std::size_t i = 0; i < 4; ++i) p[i] = {c.v[i][0], c.v[i][1], c.v[i][2]};
        for (int k = 0; k < 6; ++k) {
            long long dot = 0, nn = 0;
            bcc::dihedral_form(p, k, dot, nn);
            BOOST_TEST(dot > 0);
            BOOST_TEST(25 * dot * dot <= 9 * nn);
            BOOST_TEST(25 * dot * dot >= nn);
            lo = lo || 25 * dot * dot == 9 * nn;
            hi = hi || 25 * dot * dot == nn;
        }
    }
    BOOST_TEST(lo);
    BOOST_TEST(hi);
}

BOOST_AUTO_TEST_CASE(class_symmetries_are_the_lattice_stabilisers_of_the_references) {
    // The vertex maps induced by the lattice symmetries (with a translation
    // by 4 Z³) that map a reference onto itself are exactly `symmetries`.
    const auto ops = lattice_ops();
    for (int c = 0; c < a15::class_count; ++c) {
        const auto& ref = a15::reference_tets[static_cast<std::size_t>(c)];
        std::set<std::pair<std::array<int, 4>, std::array<int, 3>>> found;
        for (const auto& g : ops)
            for (const Ivec& target : ref) {
                const Ivec img0 = a15::apply(g, ref[0]);
                const Ivec sh = bcc::sub(target, img0);
                if (a15::floor_mod4(sh[0]) || a15::floor_mod4(sh[1]) || a15::floor_mod4(sh[2])) continue;
                std::array<int, 4> to{};
                bool ok = true;
                for (std::size_t i = 0; i < 4 && ok; ++i) {
                    const auto it = std::find(ref.begin(), ref.end(), bcc::add(a15::apply(g, ref[i]), sh));
                    ok = it != ref.end();
                    if (ok) to[i] = static_cast<int>(it - ref.begin());
                }
                if (ok) found.insert({to, g.axis});
            }
        const auto& sym = a15::symmetries[static_cast<std::size_t>(c)];
        std::set<std::pair<std::array<int, 4>, std::array<int, 3>>> listed;
        for (int i = 0; i < sym.count; ++i) listed.insert({sym.map[static_cast<std::size_t>(i)].to, sym.map[static_cast<std::size_t>(i)].axis});
        BOOST_TEST((found == listed));
    }
}

namespace {

std::array<int, 4> signs_of(int code) {
    std::array<int, 4> s{};
    for (std::size_t i = 0; i < 4; ++i, code /= 3) s[i] = code % 3 - 1;
    return s;
}

// The ten points of class c's reference with the cut points at the
// midpoints (coordinates ×2, integral).
std::array<Ivec, 10> midpoints(int c) {
    const auto& ref = a15::reference_tets[static_cast<std::size_t>(c)];
    std::array<Ivec, 10> p{};
    for (std::size_t i = 0; i < 4; ++i) p[i] = scale(ref[i], 2);
    for (std::size_t e = 0; e < 6; ++e)
        p[4 + e] = bcc::add(ref[static_cast<std::size_t>(bcc::tet_edges[e][0])], ref[static_cast<std::size_t>(bcc::tet_edges[e][1])]);
    return p;
}

}  // namespace

BOOST_AUTO_TEST_CASE(stencils_are_positive_in_every_class) {
    // Every sign pattern with a - vertex and every non-cyclic choice of
    // diagonals: each output tetrahedron is positively oriented at the
    // class's midpoint configuration (the affine argument of the header),
    // and the choices of one pattern split the same polyhedron (equal
    // volume sums).
    int outputs = 0;
    for (int c = 0; c < a15::class_count; ++c) {
        const auto P = midpoints(c);
        for (int code = 0; code < 81; ++code) {
            const auto sign = signs_of(code);
            if (std::none_of(sign.begin(), sign.end(), [](int v) { return v < 0; })) {
                BOOST_TEST(bcc::stencil_with(sign, bcc::Diagonals{}).count == 0);
                continue;
            }
            long volume = -1;
            for (unsigned face = 0; face < 16; ++face)
                for (int inside = 0; inside < 2; ++inside) {
                    const bcc::Diagonals d{face, inside != 0};
                    if (bcc::is_cyclic(sign, d)) continue;
                    const bcc::Stencil st = bcc::stencil_with(sign, d);
                    BOOST_TEST(st.count > 0);
                    long sum = 0;
                    for (int k = 0; k < st.count; ++k) {
                        const auto& t = st.tet[static_cast<std::size_t>(k)];
                        const long o = bcc::orientation({P[t[0]], P[t[1]], P[t[2]], P[t[3]]});
                        BOOST_TEST(o > 0);
                        sum += o;
                        ++outputs;
                    }
                    if (volume < 0) volume = sum;
                    BOOST_TEST(sum == volume);
                }
        }
    }
    BOOST_TEST(outputs > 3000);
}

BOOST_AUTO_TEST_CASE(face_form_is_the_empty_circle_test) {
    // On the face (a, b, r) in affine coordinates (origin a, basis b − a,
    // r − a, metric G the Gram matrix): a (0,0), b (1,0), cut(b,r)
    // (1 − u_b, u_b), cut(a,r) (0, u_a).  With Q(x) = xᵀ G x, the lifted
    // determinant D(p,q,s; x) = det[p−x, Q(p−x); q−x, Q(q−x); s−x, Q(s−x)]
    // times the orientation of (p, q, s) is invariant under affine maps, so
    // its sign tells whether x is inside the circle through p, q, s
    // (calibrated on the centroid).  a–cut(b,r) is the Delaunay diagonal iff
    // cut(a,r) is outside the circle through a, b, cut(b,r): face_form > 0;
    // on it iff face_form = 0 (both exact, ties constructed).
    std::mt19937 rng(51);
    std::uniform_int_distribution<int> num(1, 99);
    int ties = 0, decided = 0;
    using R = cpp_rational;
    using P2 = std::array<R, 2>;
    for (int c = 0; c < a15::class_count; ++c) {
        const auto& ref = a15::reference_tets[static_cast<std::size_t>(c)];
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b)
                for (int r = 0; r < 4; ++r) {
                    if (a == b || a == r || b == r) continue;
                    const Ivec e1 = bcc::sub(ref[static_cast<std::size_t>(b)], ref[static_cast<std::size_t>(a)]);
                    const Ivec e2 = bcc::sub(ref[static_cast<std::size_t>(r)], ref[static_cast<std::size_t>(a)]);
                    const R g11 = a15::norm2(e1), g22 = a15::norm2(e2), g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
                    const auto Qf = [&](const P2& x) { return x[0] * x[0] * g11 + 2 * x[0] * x[1] * g12 + x[1] * x[1] * g22; };
                    const auto lifted = [&](const P2& p, const P2& q, const P2& s, const P2& x) {
                        const P2 u{p[0] - x[0], p[1] - x[1]}, v{q[0] - x[0], q[1] - x[1]}, w{s[0] - x[0], s[1] - x[1]};
                        const R ori = (q[0] - p[0]) * (s[1] - p[1]) - (q[1] - p[1]) * (s[0] - p[0]);
                        const R D = u[0] * (v[1] * Qf(w) - Qf(v) * w[1]) - u[1] * (v[0] * Qf(w) - Qf(v) * w[0]) +
                                    Qf(u) * (v[0] * w[1] - v[1] * w[0]);
                        return ori * D;
                    };
                    for (int trial = 0; trial < 40; ++trial) {
                        const R ua(num(rng), 100);
                        R ub(num(rng), 100);
                        if (trial % 4 == 0) {  // a tie: P_a = P_b
                            ub = 1 - R(a15::local_len2(c, a, r)) * (1 - ua) / a15::local_len2(c, b, r);
                            if (ub <= 0 || ub >= 1) continue;
                        }
                        std::array<Q, 6> u{};
                        for (std::size_t e = 0; e < 6; ++e) u[e] = {R(1, 2)};
                        const int ear = bcc::edge_index(a, r), ebr = bcc::edge_index(b, r);
                        u[static_cast<std::size_t>(ear)] = {bcc::tet_edges[static_cast<std::size_t>(ear)][0] == a ? ua : 1 - ua};
                        u[static_cast<std::size_t>(ebr)] = {bcc::tet_edges[static_cast<std::size_t>(ebr)][0] == b ? ub : 1 - ub};
                        const P2 pa{0, 0}, pb{1, 0}, cb{1 - ub, ub}, ca{0, ua};
                        const P2 centroid{(pa[0] + pb[0] + cb[0]) / 3, (pa[1] + pb[1] + cb[1]) / 3};
                        const R inside = lifted(pa, pb, cb, centroid);
                        const R at_ca = lifted(pa, pb, cb, ca);
                        const R form = a15::face_form(c, a, b, r, u).q;
                        BOOST_TEST(form == -a15::face_form(c, b, a, r, u).q);
                        if (at_ca == 0) {
                            BOOST_TEST(form == 0);
                            ++ties;
                        } else {
                            BOOST_TEST(((at_ca > 0) == (inside > 0)) == (form < 0));  // ca inside: b–cut(a,r)
                            BOOST_TEST(form != 0);
                            ++decided;
                        }
                    }
                }
    }
    BOOST_TEST(ties > 100);
    BOOST_TEST(decided > 1000);
}

namespace {

// A point of a stuffed mesh by its global identity: a lattice vertex {p, p},
// or the cut point of the lattice edge {p, q}, p < q.
using PointId = std::array<Ivec, 2>;
using Triangle = std::array<PointId, 3>;

// A background tetrahedron in the lattice: its class and global vertices in
// the local order.
struct Placed {
    int cls;
    Tet v;
};

// Cut fractions per lattice edge, from its lexicographically smaller end.
using Cuts = std::map<std::pair<Ivec, Ivec>, cpp_rational>;
cpp_rational fraction_from(const Cuts& cuts, const Ivec& x, const Ivec& y) {
    return x < y ? cuts.at({x, y}) : 1 - cuts.at({y, x});
}

// The triangles of the tetrahedron's output lying in the face `face` (three
// global vertices), from the stencil of its signs under the Delaunay rule.
std::set<Triangle> output_on_face(const Placed& t, const std::map<Ivec, int>& sign_of, const Cuts& cuts,
                                  const std::set<Ivec>& face) {
    std::array<int, 4> sign{};
    for (std::size_t i = 0; i < 4; ++i) sign[i] = sign_of.at(t.v[i]);
    std::array<Q, 6> u{};
    for (std::size_t e = 0; e < 6; ++e) {
        const Ivec& x = t.v[static_cast<std::size_t>(bcc::tet_edges[e][0])];
        const Ivec& y = t.v[static_cast<std::size_t>(bcc::tet_edges[e][1])];
        u[e] = {fraction_from(cuts, x, y)};
    }
    const bcc::Stencil st = bcc::stencil_with(sign, a15::delaunay_diagonals(t.cls, sign, u, t.v));
    const auto id = [&](int q) -> PointId {
        if (q < 4) return {t.v[static_cast<std::size_t>(q)], t.v[static_cast<std::size_t>(q)]};
        const auto& e = bcc::tet_edges[static_cast<std::size_t>(q - 4)];
        const Ivec& x = t.v[static_cast<std::size_t>(e[0])];
        const Ivec& y = t.v[static_cast<std::size_t>(e[1])];
        return x < y ? PointId{x, y} : PointId{y, x};
    };
    std::set<Triangle> out;
    for (int k = 0; k < st.count; ++k)
        for (int f = 0; f < 4; ++f) {
            Triangle tri{};
            bool on = true;
            for (int j = 0, n = 0; j < 4; ++j) {
                if (j == f) continue;
                const PointId p = id(st.tet[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)]);
                on = on && face.count(p[0]) && face.count(p[1]);
                tri[static_cast<std::size_t>(n++)] = p;
            }
            if (!on) continue;
            std::sort(tri.begin(), tri.end());
            out.insert(tri);
        }
    return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(face_rule_is_conforming_between_neighbours_including_ties) {
    // Every face of every cell tetrahedron, with its neighbour across it
    // (a translate where the face crosses the cell): for every sign pattern
    // of the face with a - vertex, every sign of the two apexes, and cut
    // fractions drawn at random or tied (P_a = P_b on a quad face), both
    // tetrahedra put the same triangles on the face; on quads, the two
    // triangles of face_takes' diagonal.
    std::vector<Placed> block;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z)
                for (const auto& c : a15::cell_tets) block.push_back({c.cls, translated(c.v, {x, y, z})});
    std::map<std::set<Ivec>, std::vector<std::size_t>> faces;
    for (std::size_t i = 0; i < block.size(); ++i)
        for (std::size_t f = 0; f < 4; ++f) {
            std::set<Ivec> face;
            for (std::size_t j = 0; j < 4; ++j)
                if (j != f) face.insert(block[i].v[j]);
            faces[face].push_back(i);
        }
    std::mt19937 rng(5151);
    std::uniform_int_distribution<int> num(1, 99);
    int quads = 0, tied_quads = 0;
    const std::size_t first = 13 * a15::cell_tets.size();
    for (std::size_t i = first; i < first + a15::cell_tets.size(); ++i)
        for (std::size_t f = 0; f < 4; ++f) {
            std::set<Ivec> face;
            for (std::size_t j = 0; j < 4; ++j)
                if (j != f) face.insert(block[i].v[j]);
            const auto& owners = faces.at(face);
            const Placed& s = block[owners[0]];
            const Placed& t = block[owners[1]];
            const std::vector<Ivec> fv(face.begin(), face.end());
            Cuts cuts;
            for (const Placed* p : {&s, &t})
                for (const Ivec& x : p->v)
                    for (const Ivec& y : p->v)
                        if (x < y) cuts[{x, y}] = cpp_rational(num(rng), 100);
            for (int code = 0; code < 27 * 9; ++code) {
                std::map<Ivec, int> sign_of;
                int c = code, neg = 0;
                for (const Ivec& x : fv) {
                    sign_of[x] = c % 3 - 1;
                    neg += c % 3 == 0;
                    c /= 3;
                }
                if (neg == 0) continue;
                for (const Placed* p : {&s, &t})
                    for (const Ivec& x : p->v)
                        if (!face.count(x)) {
                            sign_of[x] = c % 3 - 1;
                            c /= 3;
                        }
                const bool quad = neg == 2 && std::any_of(fv.begin(), fv.end(), [&](const Ivec& x) { return sign_of[x] > 0; });
                for (int tie = 0; tie < (quad ? 2 : 1); ++tie) {
                    Ivec A{}, B{}, R{};
                    if (quad) {
                        std::vector<Ivec> m;
                        for (const Ivec& x : fv) (sign_of[x] < 0 ? m.push_back(x) : (void)(R = x));
                        A = m[0], B = m[1];
                        if (tie) {  // u_B from P_A = P_B
                            const cpp_rational uA = fraction_from(cuts, A, R);
                            const cpp_rational uB = 1 - cpp_rational(a15::norm2(bcc::sub(R, A))) * (1 - uA) / a15::norm2(bcc::sub(R, B));
                            if (uB <= 0 || uB >= 1) continue;
                            cuts[B < R ? std::pair{B, R} : std::pair{R, B}] = B < R ? uB : 1 - uB;
                            ++tied_quads;
                        }
                    }
                    const auto from_s = output_on_face(s, sign_of, cuts, face);
                    const auto from_t = output_on_face(t, sign_of, cuts, face);
                    BOOST_TEST((from_s == from_t));
                    BOOST_TEST(!from_s.empty());
                    if (!quad) continue;
                    ++quads;
                    const bool takes_a = a15::face_takes(A, B, R, Q{fraction_from(cuts, A, R)}, Q{fraction_from(cuts, B, R)});
                    const PointId diag_end = takes_a ? PointId{A, A} : PointId{B, B};
                    const Ivec& other = takes_a ? B : A;
                    const PointId cut_other = other < R ? PointId{other, R} : PointId{R, other};
                    BOOST_TEST(from_s.size() == 2u);
                    for (const Triangle& tri : from_s) {  // both triangles hold the diagonal
                        BOOST_TEST(std::count(tri.begin(), tri.end(), diag_end) == 1);
                        BOOST_TEST(std::count(tri.begin(), tri.end(), cut_other) == 1);
                    }
                }
            }
        }
    BOOST_TEST(quads > 9000);
    BOOST_TEST(tied_quads > 2000);
}

BOOST_AUTO_TEST_CASE(delaunay_rule_never_makes_a_cyclic_prism) {
    // n- = 3, n+ = 1 in every cell tetrahedron, with all three powers tied
    // (P_x = 2: u_x = 1 − 2/|xr|²) and at random: the global order breaks
    // ties into a total order, so the three diagonals never cycle.
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> num(1, 99);
    int prisms = 0;
    for (const auto& c : a15::cell_tets)
        for (int r = 0; r < 4; ++r)
            for (int trial = 0; trial < 20; ++trial) {
                std::array<int, 4> sign{-1, -1, -1, -1};
                sign[static_cast<std::size_t>(r)] = 1;
                std::array<Q, 6> u{};
                for (std::size_t e = 0; e < 6; ++e) u[e] = {cpp_rational(num(rng), 100)};
                if (trial < 2)
                    for (int x = 0; x < 4; ++x) {
                        if (x == r) continue;
                        const cpp_rational ux = 1 - cpp_rational(2, a15::local_len2(c.cls, x, r));
                        const auto e = static_cast<std::size_t>(bcc::edge_index(x, r));
                        u[e] = {bcc::tet_edges[e][0] == x ? ux : 1 - ux};
                    }
                const bcc::Diagonals d = a15::delaunay_diagonals(c.cls, sign, u, c.v);
                BOOST_TEST(!bcc::is_cyclic(sign, d));
                BOOST_TEST(bcc::stencil_with(sign, d).count == 3);
                ++prisms;
            }
    BOOST_TEST(prisms == 46 * 4 * 20);
}

BOOST_AUTO_TEST_CASE(thresholds_are_per_class_and_per_end) {
    const a15::Alphas a{{1, 4}, {3, 10}, {1, 5}, {2, 5}};
    BOOST_TEST(a15::valid(a));
    BOOST_TEST(!a15::valid(a15::Alphas{{1, 2}, {3, 10}, {1, 5}, {2, 5}}));
    BOOST_TEST(!a15::valid(a15::Alphas{{1, 4}, {0, 10}, {1, 5}, {2, 5}}));
    // A mixed edge's cut at 0.3 of its length from the A end violates the B
    // end? No: 0.7 from B.  At 0.19 from A it violates A (α_A = 0.2); at
    // 0.39 from B it violates B (α_B = 0.4), not at 0.4.
    BOOST_TEST(!a15::violates(a, a15::EdgeClass::mixed, true, 0.3));
    BOOST_TEST(a15::violates(a, a15::EdgeClass::mixed, true, 0.19));
    BOOST_TEST(a15::violates(a, a15::EdgeClass::mixed, false, 0.39));
    BOOST_TEST(!a15::violates(a, a15::EdgeClass::mixed, false, 0.4));
    BOOST_TEST(a15::violates(a, a15::EdgeClass::chain, false, 0.2499));
    BOOST_TEST(!a15::violates(a, a15::EdgeClass::wide, false, 0.3));
    BOOST_TEST(a15::violates(a, a15::EdgeClass::wide, true, 0.2999));
}
