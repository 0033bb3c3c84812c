// generic_a15_keys.hpp — the keys of the A15 generic tetrahedron (issue 51):
// the configuration space a prover covers and the mesher looks its
// background tetrahedra up in, defined once (as generic_bcc_keys.hpp is for
// BCC).
//
// A KEY is an a15::Config: the class, and per local vertex of the class's
// reference its post-warp sign and, for a zero vertex, its warp direction
// (index into its site's `neighbours`) or `stay`.  Its CONSISTENCY RULES,
// derived from steps 1–5 of generic_a15.hpp's contract as on BCC:
//   1. only zero vertices carry a warp (a vertex that moved is zero; - and
//      + vertices never moved);
//   2. two vertices never warp towards each other along their common edge
//      (a cut point violates one endpoint at most, every α < ½, and once an
//      endpoint moved the edge is no longer cut);
//   3. a vertex that warped along a tetrahedron edge towards vertex j found
//      j unwarped with the opposite sign: if j is zero now it warped later,
//      elsewhere, so j is not `stay`.
// Nothing else is imposed (the closest-first order's coupling, the cut
// points being zeros of one function, the signs outside the tetrahedron),
// so the space is a superset of what the mesher produces.
//
// ITS PARAMETERS (`key_params`, exact rationals; warped vertices by local
// index, then cut edges by local edge index): a warped vertex i, t_i in
// [0, α(class of its warp edge, type of i)]; a local edge e = (i, j) with
// post-warp signs - and + in either order, u_e (its fraction from i =
// bcc::tet_edges[e][0]) in [α(e's class, type of i), 1 − α(e's class, type
// of j)].
//
// ITS SYMMETRIES: a class's reference symmetries (`a15::symmetries`) map a
// key to keys with congruent (or mirror) output; the canonical key is the
// lexicographically smallest image (tuple sign₀, warp₀, …, sign₃, warp₃;
// signs −1, 0, 1; warps 0..13, `stay` = 14).  Code: the class digit, a
// colon, then per vertex its sign (-, 0, +) with, for a zero vertex, its
// warp letter a..n or s (`stay`): "1:-,0h,+,-".
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "warpmesh/mesh3d/generic_a15.hpp"

namespace warpmesh::a15 {

using Key = Config;

// The local vertex of class cls that vertex i reaches along direction w, or
// -1 (the lattice point is not a vertex of the reference).
constexpr int warp_target(int cls, int i, int w) {
    if (w == stay) return -1;
    const auto& ref = reference_tets[static_cast<std::size_t>(cls)];
    const Ivec q = bcc::add(ref[static_cast<std::size_t>(i)],
                            neighbours[static_cast<std::size_t>(reference_site(cls, i))].offset[static_cast<std::size_t>(w)]);
    for (int j = 0; j < 4; ++j)
        if (ref[static_cast<std::size_t>(j)] == q) return j;
    return -1;
}

// The consistency rules above.
constexpr bool consistent(const Key& k) {
    for (int i = 0; i < 4; ++i) {
        const int w = k.warp[static_cast<std::size_t>(i)];
        if (w != stay && k.sign[static_cast<std::size_t>(i)] != 0) return false;  // rule 1
        if (w == stay) continue;
        if (w >= neighbours[static_cast<std::size_t>(reference_site(k.cls, i))].count) return false;
        const int j = warp_target(k.cls, i, w);
        if (j < 0) continue;
        if (warp_target(k.cls, j, k.warp[static_cast<std::size_t>(j)]) == i) return false;                 // rule 2
        if (k.sign[static_cast<std::size_t>(j)] == 0 && k.warp[static_cast<std::size_t>(j)] == stay) return false;  // rule 3
    }
    return true;
}

// The image of key k under symmetry s of its class.
constexpr Key transform(const Key& k, const VertexMap& s) {
    Key out;
    out.cls = k.cls;
    const LatticeOp lin{s.axis, {0, 0, 0}};
    for (std::size_t i = 0; i < 4; ++i) {
        const auto to = static_cast<std::size_t>(s.to[i]);
        out.sign[to] = k.sign[i];
        const int w = k.warp[i];
        out.warp[to] = w == stay ? stay
                                 : direction_of(reference_site(k.cls, static_cast<int>(to)),
                                                apply_linear(lin, neighbours[static_cast<std::size_t>(reference_site(k.cls, static_cast<int>(i)))]
                                                                      .offset[static_cast<std::size_t>(w)]));
    }
    return out;
}

constexpr auto order_tuple(const Key& k) {
    std::array<int, 8> t{};
    for (std::size_t i = 0; i < 4; ++i) t[2 * i] = k.sign[i], t[2 * i + 1] = k.warp[i];
    return t;
}
// The canonical image of k (smallest order_tuple over its class's symmetries).
constexpr Key canonical(const Key& k) {
    const ClassSymmetries& sy = symmetries[static_cast<std::size_t>(k.cls)];
    Key best = k;
    for (int s = 0; s < sy.count; ++s) {
        const Key img = transform(k, sy.map[static_cast<std::size_t>(s)]);
        if (order_tuple(img) < order_tuple(best)) best = img;
    }
    return best;
}

inline std::string code_of(const Key& k) {
    std::string s = std::to_string(k.cls) + ":";
    for (std::size_t i = 0; i < 4; ++i) {
        if (i) s += ',';
        s += k.sign[i] < 0 ? '-' : k.sign[i] > 0 ? '+' : '0';
        if (k.sign[i] == 0) s += k.warp[i] == stay ? 's' : static_cast<char>('a' + k.warp[i]);
    }
    return s;
}

// Every canonical consistent key of every class with at least one - vertex
// (the keys with output; generic_a15.hpp step 6), by class then order_tuple.
inline std::vector<Key> enumerate_keys() {
    std::vector<Key> out;
    for (int cls = 0; cls < class_count; ++cls) {
        std::vector<Key> keys;
        for (int code = 0; code < 81; ++code) {
            Key k;
            k.cls = cls;
            int c = code;
            for (std::size_t i = 0; i < 4; ++i, c /= 3) k.sign[i] = c % 3 - 1;
            if (std::none_of(k.sign.begin(), k.sign.end(), [](int v) { return v < 0; })) continue;
            // every warp state of the zero vertices (an odometer)
            std::array<int, 4> limit{};
            for (std::size_t i = 0; i < 4; ++i)
                limit[i] = k.sign[i] == 0 ? neighbours[static_cast<std::size_t>(reference_site(cls, static_cast<int>(i)))].count + 1 : 1;
            std::array<int, 4> at{};
            for (bool more = true; more;) {
                for (std::size_t i = 0; i < 4; ++i)
                    k.warp[i] = k.sign[i] != 0 || at[i] == limit[i] - 1 ? stay : at[i];
                if (consistent(k) && order_tuple(canonical(k)) == order_tuple(k)) keys.push_back(k);
                more = false;
                for (std::size_t i = 0; i < 4 && !more; ++i) {
                    if (++at[i] < limit[i]) more = true;
                    else at[i] = 0;
                }
            }
        }
        std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) { return order_tuple(a) < order_tuple(b); });
        out.insert(out.end(), keys.begin(), keys.end());
    }
    return out;
}

// One parameter of a key: index 0..3 the warp fraction t of that vertex,
// 4 + e the cut fraction u_e of local edge e; its exact box [lo, hi].
struct Param {
    int index;
    Fraction lo, hi;
};
constexpr Fraction one_minus(const Fraction& f) { return {f.den - f.num, f.den}; }
// The key's parameters under thresholds al (see above).
inline std::vector<Param> key_params(const Key& k, const Alphas& al) {
    std::vector<Param> ps;
    const auto& ref = reference_tets[static_cast<std::size_t>(k.cls)];
    for (int i = 0; i < 4; ++i) {
        const int w = k.warp[static_cast<std::size_t>(i)];
        if (w == stay) continue;
        const int s = reference_site(k.cls, i);
        const EdgeClass c = edge_class(neighbours[static_cast<std::size_t>(s)].offset[static_cast<std::size_t>(w)]);
        ps.push_back({i, {0, 1}, threshold(al, c, site_is_a(s))});
    }
    for (int e = 0; e < 6; ++e) {
        const int i = bcc::tet_edges[static_cast<std::size_t>(e)][0], j = bcc::tet_edges[static_cast<std::size_t>(e)][1];
        if (k.sign[static_cast<std::size_t>(i)] * k.sign[static_cast<std::size_t>(j)] >= 0) continue;
        const EdgeClass c = edge_class(bcc::sub(ref[static_cast<std::size_t>(j)], ref[static_cast<std::size_t>(i)]));
        ps.push_back({4 + e, threshold(al, c, site_is_a(reference_site(k.cls, i))),
                      one_minus(threshold(al, c, site_is_a(reference_site(k.cls, j))))});
    }
    return ps;
}

}  // namespace warpmesh::a15
