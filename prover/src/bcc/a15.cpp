// a15.cpp — A15 keys as subjects of the 3D prover (issue 51): their
// parameter boxes and the stencils the A15 Delaunay rule admits on a box
// (generic_a15.hpp, "The face rule"), so that the BCC branch and bound
// (bound.cpp) and witness search (targets.cpp) run unchanged on them.
#include <algorithm>
#include <cmath>

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

bcc::Stencil a15_stencil_at(const Subject& s, const double* x) {
    std::array<double, 6> u{};
    for (std::size_t i = 0; i < s.ps.size(); ++i)
        if (s.ps[i].index >= 4) u[static_cast<std::size_t>(s.ps[i].index - 4)] = x[i];
    std::array<int, 4> fs{};
    for (int f = 0; f < 4; ++f) {
        int a = -1, b = -1, r = -1;
        if (bcc::quad_face(s.key.sign, f, a, b, r)) fs[static_cast<std::size_t>(f)] = decided_sign(a15::face_form(s.a15_class, a, b, r, u)).value();
    }
    int a = -1, b = -1, r0 = -1, r1 = -1, is = 0;
    if (bcc::inside_quad(s.key.sign, a, b, r0, r1)) is = decided_sign(a15::inside_form(s.a15_class, a, b, r0, r1, u)).value();
    const bcc::Diagonals d = a15::resolve_delaunay(s.key.sign, fs, {true, true, true, true}, is);
    return bcc::stencil_with(s.key.sign, d);
}

}  // namespace warpmesh::bcc_prover
