// prove_graded.cpp — `warpmesh-prove-bcc --graded`: the transition templates
// of graded meshes (mesh3d/generic_octree.hpp) certified exactly and written
// to proofs/bcc_graded.cert (format: proofs/README.md, "Graded transitions").
//
// A template is a fixed tetrahedron with integer (doubled lattice)
// coordinates, so no branch and bound is needed: for each of the 17
// configurations the fan's tetrahedra come from the one definition
// (transition_config, piece_tets), and their forms — 6·volume, per edge
// d = n_c·n_d and N = |n_c|²|n_d|², per face angle s = u·v and M = |u|²|v|²
// (generic_bcc.hpp's dihedral_forms and face_angle_forms, instantiated on
// 64-bit integers: every value is exact) — give each tetrahedron's exact
// extremes d²/N over its acute (d > 0) and obtuse (d < 0) dihedral angles and
// s²/M over its acute face angles, reduced rationals: the witnesses.  The
// claim is each extreme over all templates rounded up to a multiple of
// 2^-40, plus 2^-30 of margin (the mesher's double-precision verify then
// never fails on rounding).  No transcendental function on the proof path:
// degrees appear only in the certificate's comment.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>

#include "warpmesh/mesh3d/generic_octree.hpp"
#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {
namespace {

using I = long long;
using I128 = __int128;

// A non-negative rational p / q (q > 0), or none (q = 0).
struct Ratio {
    I128 p = 0, q = 0;
};
bool greater(const Ratio& a, const Ratio& b) { return b.q == 0 ? a.q != 0 : a.q != 0 && a.p * b.q > b.p * a.q; }
std::string text(I128 v) {
    if (v == 0) return "0";
    std::string s;
    const bool neg = v < 0;
    for (I128 x = neg ? -v : v; x > 0; x /= 10) s.insert(s.begin(), static_cast<char>('0' + static_cast<int>(x % 10)));
    return neg ? "-" + s : s;
}
std::string text(const Ratio& r) {
    if (r.q == 0) return "-";
    I128 a = r.p, b = r.q;
    while (b != 0) a %= b, std::swap(a, b);
    return text(r.p / a) + "/" + text(r.q / a);
}

// The extremes of one tetrahedron: [0] largest d²/N with d > 0 (the smallest
// dihedral angle), [1] largest d²/N with d < 0 (the largest), [2] largest s²/M
// with s > 0 (the smallest face angle).
struct Extremes {
    std::array<Ratio, 3> r;
    I volume6 = 0;
};
Extremes extremes(const bcc::LatticeTet& t) {
    std::array<bcc::Vec<I>, 4> p{};
    for (std::size_t k = 0; k < 4; ++k) p[k] = {t[k][0], t[k][1], t[k][2]};
    const auto f = bcc::dihedral_forms<I>(p);
    const auto g = bcc::face_angle_forms<I>(p);
    Extremes e;
    e.volume6 = f.volume6;
    for (std::size_t k = 0; k < 6; ++k) {
        const Ratio c{static_cast<I128>(f.dot[k]) * f.dot[k], f.nn[k]};
        Ratio& slot = e.r[f.dot[k] > 0 ? 0 : 1];
        if (f.dot[k] != 0 && greater(c, slot)) slot = c;
    }
    for (std::size_t q = 0; q < 12; ++q) {
        const Ratio c{static_cast<I128>(g.dot[q]) * g.dot[q], g.nn[q]};
        if (g.dot[q] > 0 && greater(c, e.r[2])) e.r[2] = c;
    }
    return e;
}

// The claim numerator over 2^40: floor(r · 2^40) + 1 + 2^10.
I128 claim40(const Ratio& r) { return r.q == 0 ? 0 : (r.p << 40) / r.q + 1 + 1024; }

double degrees(const Ratio& r, bool obtuse) {  // comments only
    const double a = std::acos(std::sqrt(static_cast<double>(r.p) / static_cast<double>(r.q))) * 180 / M_PI;
    return obtuse ? 180 - a : a;
}

}  // namespace

int prove_graded(const std::string& out) {
    std::ostringstream body;
    std::array<Ratio, 3> worst{};
    int total = 0;
    for (int k = 0; k < bcc::transition_configs; ++k) {
        std::array<bcc::LatticeTet, 8> tets{};
        const int n = bcc::piece_tets(bcc::transition_config(k), tets);
        body << "config " << k << " " << n << "\n";
        for (int i = 0; i < n; ++i) {
            const bcc::LatticeTet& t = tets[static_cast<std::size_t>(i)];
            const Extremes e = extremes(t);
            if (e.volume6 <= 0) {
                std::fprintf(stderr, "warpmesh-prove-bcc --graded: configuration %d has a tetrahedron that is not positively oriented\n", k);
                return 1;
            }
            body << "tet";
            for (const bcc::Ivec& v : t) body << " " << v[0] << " " << v[1] << " " << v[2];
            for (std::size_t j = 0; j < 3; ++j) {
                body << " " << text(e.r[j]);
                if (greater(e.r[j], worst[j])) worst[j] = e.r[j];
            }
            body << "\n";
            ++total;
        }
    }
    std::ofstream f(out);
    char comment[256];
    std::snprintf(comment, sizeof comment, "# witnesses: dihedral angles %.6f to %.6f deg, face angles from %.6f deg\n",
                  degrees(worst[0], false), degrees(worst[1], true), degrees(worst[2], false));
    f << "warpmesh-bcc-graded 1\n"
      << "# Transition templates of graded BCC meshes (mesh3d/generic_octree.hpp).  Format: proofs/README.md, \"Graded transitions\".\n"
      << comment << "claim " << text(claim40(worst[0])) << "/1099511627776 " << text(claim40(worst[1])) << "/1099511627776 "
      << text(claim40(worst[2])) << "/1099511627776\n"
      << "configs " << bcc::transition_configs << "\n"
      << body.str();
    if (!f) {
        std::fprintf(stderr, "warpmesh-prove-bcc --graded: cannot write %s\n", out.c_str());
        return 1;
    }
    std::fprintf(stderr, "warpmesh-prove-bcc --graded: %d template tetrahedra in %d configurations -> %s\n", total, bcc::transition_configs,
                 out.c_str());
    return 0;
}

}  // namespace warpmesh::bcc_prover
