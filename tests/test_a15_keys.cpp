// The keys of the A15 generic tetrahedron (generic_a15_keys.hpp): the
// symmetries act geometrically (an image's points are the symmetry's image
// of the key's points, exactly); the enumeration holds every background
// tetrahedron of stuffings of random spheres done by the mesher's contract
// (generic_a15.hpp, steps 1–5, implemented here independently of any
// mesher), canonicalised, with its parameters inside the key's box.
#define BOOST_TEST_MODULE a15_keys
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "warpmesh/mesh3d/generic_a15_keys.hpp"
#include "exact_rational.hpp"

using namespace warpmesh;
using a15::Ivec;
using boost::multiprecision::cpp_rational;
using warpmesh::testing::Q;

BOOST_AUTO_TEST_CASE(key_counts) {
    // The canonical consistent keys with a - vertex, per class (pinned; the
    // checker is to re-derive them on its own).
    const auto keys = a15::enumerate_keys();
    std::array<int, 3> n{};
    int params = 0;
    const a15::Alphas al{{1, 4}, {3, 10}, {1, 5}, {2, 5}};
    for (const auto& k : keys) {
        ++n[static_cast<std::size_t>(k.cls)];
        BOOST_TEST(a15::consistent(k));
        BOOST_TEST((a15::order_tuple(a15::canonical(k)) == a15::order_tuple(k)));
        params = std::max(params, static_cast<int>(a15::key_params(k, al).size()));
    }
    BOOST_TEST(keys.size() == 15535u);
    BOOST_TEST(n[0] == 8013);
    BOOST_TEST(n[1] == 5275);
    BOOST_TEST(n[2] == 2247);
    BOOST_TEST(params == 4);
    BOOST_TEST(a15::code_of(keys.front()).substr(0, 2) == "0:");
}

BOOST_AUTO_TEST_CASE(symmetries_act_geometrically) {
    // For sampled keys and every symmetry (to, M) of their class: the
    // image's points at the moved parameters are M times the key's points
    // plus one translation, exactly (so angles, orientation up to det M, and
    // the face rule's forms are those of the key).
    const auto keys = a15::enumerate_keys();
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> num(1, 9);
    int checked = 0;
    for (std::size_t n = 0; n < keys.size(); n += 7) {
        const a15::Key& k = keys[n];
        std::array<Q, 4> t{};
        std::array<Q, 6> u{};
        for (auto& x : t) x = {cpp_rational(num(rng), 40)};
        for (auto& x : u) x = {cpp_rational(num(rng), 10)};
        const auto P = a15::generic_points(k, t, u);
        const auto& sy = a15::symmetries[static_cast<std::size_t>(k.cls)];
        for (int s = 0; s < sy.count; ++s) {
            const auto& m = sy.map[static_cast<std::size_t>(s)];
            const a15::Key img = a15::transform(k, m);
            BOOST_TEST(a15::consistent(img));
            std::array<Q, 4> t2{};
            std::array<Q, 6> u2{};
            for (std::size_t i = 0; i < 4; ++i) t2[static_cast<std::size_t>(m.to[i])] = t[i];
            for (std::size_t e = 0; e < 6; ++e) {
                const int i = bcc::tet_edges[e][0], j = bcc::tet_edges[e][1];
                const int ti = m.to[static_cast<std::size_t>(i)], tj = m.to[static_cast<std::size_t>(j)];
                const auto e2 = static_cast<std::size_t>(bcc::edge_index(ti, tj));
                u2[e2] = bcc::tet_edges[e2][0] == ti ? u[e] : Q{1 - u[e].q};
            }
            const auto P2 = a15::generic_points(img, t2, u2);
            const a15::LatticeOp lin{m.axis, {0, 0, 0}};
            // image point of key point q: M P[q] + shift, shift fixed by vertex 0.
            const auto mapped = [&](std::size_t q, std::size_t k3) {
                cpp_rational v = 0;
                Ivec unit{0, 0, 0};
                for (std::size_t c = 0; c < 3; ++c) {
                    unit = {0, 0, 0};
                    unit[c] = 1;
                    const Ivec col = a15::apply_linear(lin, unit);
                    v += col[k3] * P[q][c].q;
                }
                return v;
            };
            const auto qmap = [&](std::size_t q) -> std::size_t {
                if (q < 4) return static_cast<std::size_t>(m.to[q]);
                const auto& e = bcc::tet_edges[q - 4];
                return 4 + static_cast<std::size_t>(bcc::edge_index(m.to[static_cast<std::size_t>(e[0])], m.to[static_cast<std::size_t>(e[1])]));
            };
            std::array<cpp_rational, 3> shift{};
            for (std::size_t c = 0; c < 3; ++c) shift[c] = P2[qmap(0)][c].q - mapped(0, c);
            for (std::size_t q = 0; q < 10; ++q)
                for (std::size_t c = 0; c < 3; ++c) BOOST_TEST((P2[qmap(q)][c].q == mapped(q, c) + shift[c]));
            ++checked;
        }
    }
    BOOST_TEST(checked > 3000);
}

namespace {

// Steps 1–5 of generic_a15.hpp's contract on the cells [0, 4)³ for the
// sphere |x − c| = R (quadrupled coordinates, f < 0 inside), c in [6, 10]³
// and R <= 3.5: every - site and its neighbours lie in the block, so no
// cut edge leaves it.
struct Stuffed {
    std::map<Ivec, int> sign;                           // post-warp
    std::map<Ivec, std::pair<Ivec, double>> warp;       // offset, fraction
    std::map<std::pair<Ivec, Ivec>, double> cut;        // fraction from first (p < q)
};
bool in_block(const Ivec& q) { return q[0] >= 0 && q[0] < 16 && q[1] >= 0 && q[1] < 16 && q[2] >= 0 && q[2] < 16; }

Stuffed stuff(const std::array<double, 3>& c, double R, const a15::Alphas& al) {
    Stuffed s;
    const auto f = [&](const Ivec& p) {
        double d = 0;
        for (std::size_t k = 0; k < 3; ++k) d += (p[k] - c[k]) * (p[k] - c[k]);
        return d - R * R;
    };
    std::vector<Ivec> sites;
    for (int x = 0; x < 4; ++x)
        for (int y = 0; y < 4; ++y)
            for (int z = 0; z < 4; ++z)
                for (const Ivec& p : a15::sites) sites.push_back(bcc::add(p, {4 * x, 4 * y, 4 * z}));
    for (const Ivec& p : sites) s.sign[p] = f(p) < 0 ? -1 : f(p) > 0 ? 1 : 0;  // step 1
    std::vector<bcc::Violation> viol;
    for (const Ivec& p : sites) {
        const int sp = a15::site_of(p);
        const auto& nb = a15::neighbours[static_cast<std::size_t>(sp)];
        for (int i = 0; i < nb.count; ++i) {
            const Ivec d = nb.offset[static_cast<std::size_t>(i)];
            const Ivec q = bcc::add(p, d);
            if (!(p < q) || !in_block(q) || s.sign[p] * s.sign[q] >= 0) continue;
            // step 2: the zero of f on p–q (the root of a quadratic in (0, 1))
            double a = 0, b = 0;
            for (std::size_t k = 0; k < 3; ++k) a += d[k] * d[k], b += 2 * d[k] * (p[k] - c[k]);
            const double cc = f(p), disc = std::sqrt(b * b - 4 * a * cc);
            double u = (-b - disc) / (2 * a);
            if (!(u > 0 && u < 1)) u = (-b + disc) / (2 * a);
            BOOST_REQUIRE((u > 0 && u < 1));
            s.cut[{p, q}] = u;
            const a15::EdgeClass ec = a15::edge_class(d);
            const int sq = a15::site_of(q);
            // step 3
            if (a15::violates(al, ec, a15::site_is_a(sp), u)) viol.push_back({u, p, i});
            if (a15::violates(al, ec, a15::site_is_a(sq), 1 - u))
                viol.push_back({1 - u, q, a15::direction_of(sq, bcc::sub(p, q))});
        }
    }
    std::sort(viol.begin(), viol.end(), bcc::warp_before);  // step 4
    for (const bcc::Violation& v : viol) {
        const Ivec d = a15::neighbours[static_cast<std::size_t>(a15::site_of(v.vertex))].offset[static_cast<std::size_t>(v.direction)];
        const Ivec w = bcc::add(v.vertex, d);
        if (s.warp.count(v.vertex) || s.warp.count(w)) continue;
        s.warp[v.vertex] = {d, v.frac};
        s.sign[v.vertex] = 0;
    }
    return s;
}

}  // namespace

BOOST_AUTO_TEST_CASE(stuffed_spheres_have_enumerated_keys_inside_their_boxes) {
    const auto keys = a15::enumerate_keys();
    std::set<std::string> codes;
    for (const auto& k : keys) codes.insert(a15::code_of(k));
    std::mt19937 rng(51);
    std::uniform_real_distribution<double> centre(6, 10), radius(1.5, 3.5);
    const std::array<a15::Alphas, 3> alphas{a15::Alphas{{1, 4}, {3, 10}, {1, 5}, {2, 5}},
                                            a15::Alphas{{49, 100}, {49, 100}, {49, 100}, {49, 100}},
                                            a15::Alphas{{2, 5}, {1, 10}, {9, 20}, {3, 10}}};
    std::set<std::string> seen;
    long tets = 0, warped = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const a15::Alphas& al = alphas[static_cast<std::size_t>(trial % 3)];
        const Stuffed s = stuff({centre(rng), centre(rng), centre(rng)}, radius(rng), al);
        warped += static_cast<long>(s.warp.size());
        for (int x = 0; x < 4; ++x)
            for (int y = 0; y < 4; ++y)
                for (int z = 0; z < 4; ++z)
                    for (const auto& ct : a15::cell_tets) {
                        a15::Key k;
                        k.cls = ct.cls;
                        std::array<Ivec, 4> v{};
                        bool inside = true;
                        for (std::size_t i = 0; i < 4; ++i) {
                            v[i] = bcc::add(ct.v[i], {4 * x, 4 * y, 4 * z});
                            inside = inside && in_block(v[i]);
                        }
                        if (!inside) continue;
                        std::array<double, 4> t{};
                        for (std::size_t i = 0; i < 4; ++i) {
                            k.sign[i] = s.sign.at(v[i]);
                            const auto w = s.warp.find(v[i]);
                            if (w == s.warp.end()) continue;
                            k.warp[i] = a15::direction_of(a15::reference_site(k.cls, static_cast<int>(i)), a15::to_local(ct.op, w->second.first));
                            t[i] = w->second.second;
                        }
                        if (std::none_of(k.sign.begin(), k.sign.end(), [](int g) { return g < 0; })) continue;
                        ++tets;
                        BOOST_TEST(a15::consistent(k));
                        const std::string code = a15::code_of(a15::canonical(k));
                        BOOST_TEST(codes.count(code) == 1u, code);
                        seen.insert(code);
                        for (const a15::Param& p : a15::key_params(k, al)) {
                            double x = 0;
                            if (p.index < 4) x = t[static_cast<std::size_t>(p.index)];
                            else {
                                const auto& e = bcc::tet_edges[static_cast<std::size_t>(p.index - 4)];
                                const Ivec& a = v[static_cast<std::size_t>(e[0])];
                                const Ivec& b = v[static_cast<std::size_t>(e[1])];
                                x = a < b ? s.cut.at({a, b}) : 1 - s.cut.at({b, a});
                            }
                            BOOST_TEST(x * static_cast<double>(p.lo.den) >= static_cast<double>(p.lo.num) - 1e-9);
                            BOOST_TEST(x * static_cast<double>(p.hi.den) <= static_cast<double>(p.hi.num) + 1e-9);
                        }
                    }
    }
    BOOST_TEST(tets > 3000);
    BOOST_TEST(warped > 500);
    BOOST_TEST(seen.size() > 300u);
    BOOST_TEST_MESSAGE("A15 keys seen: " << seen.size() << " of " << keys.size() << " over " << tets << " tetrahedra");
}
