// a15.cpp — A15 keys as subjects of the 3D prover (issue 51): their
// parameter boxes and the stencils the A15 Delaunay rule admits on a box
// (generic_a15.hpp, "The face rule"), so that the BCC branch and bound
// (bound.cpp) and witness search (targets.cpp) run unchanged on them.
#include <algorithm>
#include <cmath>

#include "warpmesh/exact_rational.hpp"
#include "warpmesh/numerics/interval.hpp"
#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {
namespace {

double dyadic_floor(double x) { return std::floor(std::ldexp(x, 20)) / 1048576.0; }
double dyadic_ceil(double x) { return std::ceil(std::ldexp(x, 20)) / 1048576.0; }
double to_double(const a15::Fraction& f) { return static_cast<double>(f.num) / static_cast<double>(f.den); }

// The cut fractions of the subject's parameters (others 0) at box b, as T.
template <class T>
std::array<T, 6> cut_fractions(const Subject& s, const Box& b) {
    std::array<T, 6> u{};
    for (std::size_t i = 0; i < s.ps.size(); ++i)
        if (s.ps[i].index >= 4) u[static_cast<std::size_t>(s.ps[i].index - 4)] = T(b.lo[i], b.hi[i]);
    return u;
}

}  // namespace

// Root boxes as for BCC keys (keys.cpp): the exact ends rounded to nearest
// lie within 2^-53 relative of the rationals, so one unit of 2^-20 outward
// encloses them.
Subject a15_subject(const a15::Key& k, const a15::Alphas& al) {
    Subject s;
    s.key.sign = k.sign, s.key.warp = k.warp, s.key.parity = 0;
    s.a15_class = k.cls;
    s.rule = FaceRule::delaunay;
    s.seed = a15::code_of(k);
    s.a15_alphas = al;
    for (const a15::Param& p : a15::key_params(k, al)) {
        const double lo = to_double(p.lo), hi = to_double(p.hi);
        s.ps.push_back({p.index, lo, hi, p.lo.num == 0 ? 0.0 : dyadic_floor(lo - 0x1p-20), dyadic_ceil(hi + 0x1p-20)});
    }
    return s;
}

std::vector<bcc::Stencil> admissible_a15_stencils(const Subject& s, const Box& b) {
    const RoundUp guard;
    const std::array<Interval, 6> u = cut_fractions<Interval>(s, b);
    const int cls = s.a15_class;
    const auto& sign = s.key.sign;
    // adm[f]: the signs admitted for the quad of the face without vertex f
    // ({0}: no quad); adm[4]: for the inside quad.  Decided: alone; an
    // enclosure containing 0 (a tie inside the box, or undecided): both.
    const auto admitted = [](const std::optional<int>& x) {
        if (x && *x != 0) return std::vector<int>{*x};
        return std::vector<int>{-1, 1};
    };
    std::array<std::vector<int>, 5> adm;
    for (int f = 0; f < 4; ++f) {
        int a = -1, bb = -1, r = -1;
        adm[static_cast<std::size_t>(f)] =
            bcc::quad_face(sign, f, a, bb, r) ? admitted(decided_sign(a15::face_form(cls, a, bb, r, u))) : std::vector<int>{0};
    }
    int a = -1, bb = -1, r0 = -1, r1 = -1;
    adm[4] = bcc::inside_quad(sign, a, bb, r0, r1) ? admitted(decided_sign(a15::inside_form(cls, a, bb, r0, r1, u)))
                                                  : std::vector<int>{0};
    return stencils_of_signs(sign, adm, [&](const std::array<int, 4>& fs, int inside) {
        return a15::resolve_delaunay(sign, fs, {}, inside);
    });
}

bool a15_exact_end(const Subject& s, std::size_t i, double x, a15::Fraction& end) {
    const double g = std::ldexp(x, 24);
    if (g == std::floor(g)) return false;
    const a15::Param p = a15::key_params(a15_key(s), s.a15_alphas)[i];
    for (const a15::Fraction& f : {p.lo, p.hi})
        if (x == to_double(f)) return end = f, true;
    return false;
}

bcc::Stencil a15_stencil_at(const Subject& s, const double* x) {
    const auto& ref = a15::reference_tets[static_cast<std::size_t>(s.a15_class)];
    bool exact = false;
    std::array<rational::Q, 6> uq{};
    std::array<double, 6> u{};
    for (std::size_t i = 0; i < s.ps.size(); ++i) {
        if (s.ps[i].index < 4) continue;
        const auto e = static_cast<std::size_t>(s.ps[i].index - 4);
        u[e] = x[i];
        a15::Fraction f{};
        if (a15_exact_end(s, i, x[i], f)) uq[e] = {boost::multiprecision::cpp_rational(f.num, f.den)}, exact = true;
        else uq[e] = {boost::multiprecision::cpp_rational(static_cast<long long>(std::ldexp(x[i], 24)), 16777216)};
    }
    // Near a tie the double forms (the inside form's squares need 54 bits on
    // the grid) may not decide exactly: decide them in rationals there too.
    for (int f = 0, a, b, r; f < 4 && !exact; ++f)
        exact = bcc::quad_face(s.key.sign, f, a, b, r) && std::fabs(a15::face_form(s.a15_class, a, b, r, u)) < 1e-9;
    int a = -1, b = -1, r0 = -1, r1 = -1;
    exact = exact || (bcc::inside_quad(s.key.sign, a, b, r0, r1) && std::fabs(a15::inside_form(s.a15_class, a, b, r0, r1, u)) < 1e-9);
    return bcc::stencil_with(s.key.sign, exact ? a15::delaunay_diagonals(s.a15_class, s.key.sign, uq, ref)
                                               : a15::delaunay_diagonals(s.a15_class, s.key.sign, u, ref));
}

}  // namespace warpmesh::bcc_prover
