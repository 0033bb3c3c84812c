// bound.cpp — branch and bound over a BCC key's parameter box: evaluates
// generic_bcc.hpp's own points, stencil and dihedral forms with
// outward-rounded intervals and verifies, box by box, positive orientation
// and both angle bounds of every output tetrahedron (proofs/README.md,
// "The BCC certificate").
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "warpmesh/numerics/dual.hpp"
#include "warpmesh/numerics/interval.hpp"
#include "warpmesh/prove_bcc.hpp"

namespace warpmesh {

// Outward-rounded intervals, as in the 2D prover (numerics/interval.hpp:
// every entry point below holds a RoundUp guard), and dual numbers over them
// (numerics/dual.hpp): value and the partials in the (at most 4) parameters
// (DI), and the second partials too (D2).  Points are affine in the
// parameters, the forms polynomials.
namespace bcc_prover {
using BI = Interval;
using DI = Dual<Interval>;
using D2 = Dual2<Interval>;

namespace {

// The dihedral and face-angle forms of one output tetrahedron.
template <class T>
struct TetForms {
    bcc::DihedralForms<T> di;
    bcc::FaceAngleForms<T> fa;
};
// The subject's points on box b (T = DI: with partials; T = D2: and second
// partials); parameters not in the subject's list are 0 (no point its
// tetrahedra use depends on them).
template <class T = DI>
std::array<bcc::Vec<T>, 15> box_points(const Subject& s, const Box& b) {
    const T zero = ScalarOps<T>::from_int(0);
    std::array<T, 4> t{zero, zero, zero, zero};
    std::array<T, 6> u{zero, zero, zero, zero, zero, zero};
    for (std::size_t i = 0; i < s.ps.size(); ++i) {
        T x = zero;
        x.v = BI(b.lo[i], b.hi[i]);
        x.d[i] = BI(1.);
        if (s.ps[i].index < 4) t[static_cast<std::size_t>(s.ps[i].index)] = x;
        else u[static_cast<std::size_t>(s.ps[i].index - 4)] = x;
    }
    return subject_points<T>(s, t, u);
}
// The forms of output tetrahedron `tet` (points of the subject).
template <class T>
TetForms<T> tet_forms(const std::array<bcc::Vec<T>, 15>& pts, const bcc::OutTet& tet) {
    std::array<bcc::Vec<T>, 4> p{};
    for (std::size_t v = 0; v < 4; ++v) p[v] = pts[tet[v]];
    return {bcc::dihedral_forms(p), bcc::face_angle_forms(p)};
}
// The forms of the output tetrahedra `tets` on box b.
template <class T = DI>
std::vector<TetForms<T>> all_forms(const Subject& s, const Box& b, const std::vector<bcc::OutTet>& tets) {
    const auto pts = box_points<T>(s, b);
    std::vector<TetForms<T>> out;
    for (const bcc::OutTet& tet : tets) out.push_back(tet_forms(pts, tet));
    return out;
}
Box centre(const Box& b) {
    Box m = b;
    for (std::size_t i = 0; i < static_cast<std::size_t>(b.m); ++i) m.lo[i] = m.hi[i] = 0.5 * (b.lo[i] + b.hi[i]);
    return m;
}

bool same(const bcc::Stencil& a, const bcc::Stencil& b) {
    if (a.count != b.count) return false;
    for (std::size_t j = 0; j < static_cast<std::size_t>(a.count); ++j)
        if (a.tet[j] != b.tet[j]) return false;
    return true;
}

// The output tetrahedra to verify on box b: a junction face's cone
// tetrahedra; the key's stencil (parity), or every tetrahedron of every
// admissible stencil, each once (Delaunay; A15 keys: their rule).
std::vector<bcc::OutTet> box_tets(const Subject& s, const Box& b) {
    if (s.junction) return s.tets;
    const std::vector<bcc::Stencil> sts = s.a15_class >= 0             ? admissible_a15_stencils(s, b)
                                          : s.rule == FaceRule::parity ? std::vector<bcc::Stencil>{bcc::stencil(s.key.sign, s.key.parity)}
                                                                     : admissible_stencils(s.key, s.ps, b);
    std::vector<bcc::OutTet> out;
    for (const bcc::Stencil& st : sts)
        for (std::size_t j = 0; j < static_cast<std::size_t>(st.count); ++j)
            if (std::find(out.begin(), out.end(), st.tet[j]) == out.end()) out.push_back(st.tet[j]);
    return out;
}

// Form f of one tetrahedron's forms: f = 0: 6·volume; f = 1 + 2e: -d_e;
// 2 + 2e: C_min N_e - d_e²; f = 13 + 2e: d_e; 14 + 2e: C_max N_e - d_e²
// (d = n_c·n_d, N = |n_c|²|n_d|²); f = 25 + 2q: -s_q, 26 + 2q: F M_q - s_q²
// (face angle q: s = u·v, M = |u|²|v|²).
template <class T>
T form_of(const TetForms<T>& tf, int f, const Claim& c) {
    const T zero = ScalarOps<T>::from_int(0);
    const auto& df = tf.di;
    if (f == 0) return df.volume6;
    if (f >= 25) {
        const auto q = static_cast<std::size_t>((f - 25) / 2);
        if ((f - 25) % 2 == 0) return zero - tf.fa.dot[q];
        T cc = zero;
        cc.v = BI(c.cface);
        return cc * tf.fa.nn[q] - tf.fa.dot[q] * tf.fa.dot[q];
    }
    const int g = (f - 1) % 12, e = g / 2;
    const T& d = df.dot[static_cast<std::size_t>(e)];
    if (g % 2 == 0) return f < 13 ? zero - d : d;
    T cc = zero;
    cc.v = BI(f < 13 ? c.cmin : c.cmax);
    return cc * df.nn[static_cast<std::size_t>(e)] - d * d;
}

// Form f alone (form_of(tet_forms(pts, tet), f, c), computed alike: the same
// operations in the same order, so the same enclosure).
template <class T>
T one_form(const std::array<bcc::Vec<T>, 15>& pts, const bcc::OutTet& tet, int f, const Claim& c) {
    std::array<bcc::Vec<T>, 4> p{};
    for (std::size_t v = 0; v < 4; ++v) p[v] = pts[tet[v]];
    if (f == 0) return bcc::volume6_form(p);
    const T zero = ScalarOps<T>::from_int(0);
    T d = zero, nn = zero, cc = zero;
    if (f >= 25) {
        bcc::face_angle_form(p, (f - 25) / 2, d, nn);
        if ((f - 25) % 2 == 0) return zero - d;
        cc.v = BI(c.cface);
        return cc * nn - d * d;
    }
    const int g = (f - 1) % 12;
    bcc::dihedral_form(p, g / 2, d, nn);
    if (g % 2 == 0) return f < 13 ? zero - d : d;
    cc.v = BI(f < 13 ? c.cmin : c.cmax);
    return cc * nn - d * d;
}

// The second-order Taylor form of form f of tetrahedron j on box b around its
// centre m: g(m) + sum_i g_i(m) [-r_i, r_i] + sum_i g_ii(b) [0, r_i²] / 2
// + sum_{i<l} g_il(b) [-r_i r_l, r_i r_l] (the partials at the point m, the
// second partials on the box).
BI taylor2(const Subject& s, const Box& b, const bcc::OutTet& tet, int f, const Claim& c) {
    const DI g = one_form(box_points(s, centre(b)), tet, f, c);
    const D2 h = one_form(box_points<D2>(s, b), tet, f, c);
    BI t = g.v;
    for (std::size_t i = 0; i < static_cast<std::size_t>(b.m); ++i) {
        const BI r = BI(0.5 * (b.hi[i] - b.lo[i]));
        t = t + g.d[i] * BI(-r.upper(), r.upper()) + BI(0.5) * h.h[i][i] * BI(0., (r * r).upper());
        for (std::size_t l = i + 1; l < static_cast<std::size_t>(b.m); ++l) {
            const double rr = (r * BI(0.5 * (b.hi[l] - b.lo[l]))).upper();
            t = t + h.h[i][l] * BI(-rr, rr);
        }
    }
    return t;
}

// g >= 0 (strict: > 0) on box b.  Tests, in turn, the natural enclosure g(b)
// and the mean-value form around the centre m of b, g(m) + sum_j g_j(b)
// [-r_j, r_j]; while neither proves it, every variable whose partial has a
// decided sign on the box is fixed at the end where g is smaller (all at
// once), and both tests are repeated on that face (the 2D prover's
// procedure, bound.cpp, verify_poly); where nothing is fixed, the
// second-order Taylor form on that face.  The checker applies it exactly.
// `g` is the form on b, `mid` its value at the centre (both precomputed for
// all forms of the box).
bool verify_form(const Subject& s, Box b, const bcc::OutTet& tet, int f, const Claim& c, bool strict, DI g, BI mid) {
    for (bool first = true;; first = false) {
        if (strict ? g.v.lower() > 0 : g.v.lower() >= 0) return true;
        BI mv = first ? mid : one_form(box_points(s, centre(b)), tet, f, c).v;
        for (std::size_t i = 0; i < static_cast<std::size_t>(b.m); ++i)
            if (b.lo[i] != b.hi[i]) {
                const double r = 0.5 * (b.hi[i] - b.lo[i]);
                mv = mv + g.d[i] * BI(-r, r);
            }
        if (strict ? mv.lower() > 0 : mv.lower() >= 0) return true;
        bool fixed = false;
        for (std::size_t i = 0; i < static_cast<std::size_t>(b.m); ++i) {
            if (b.lo[i] == b.hi[i]) continue;
            if (g.d[i].lower() >= 0) b.hi[i] = b.lo[i], fixed = true;
            else if (g.d[i].upper() <= 0) b.lo[i] = b.hi[i], fixed = true;
        }
        if (!fixed) {
            const BI t = taylor2(s, b, tet, f, c);
            return strict ? t.lower() > 0 : t.lower() >= 0;
        }
        g = one_form(box_points(s, b), tet, f, c);
    }
}

// Whether every output tetrahedron of key k (every tetrahedron of every
// stencil the rule admits on the box) is positively oriented with all
// dihedral angles in the claim on the box; `fail` gets what failed (0
// orientation, 1 minimum, 2 maximum, 4 face angle) and `smear` the failed form's smear per
// parameter, |∂_i g(box)|·width_i (of the alternative tried first), which
// chooses the side to split.  Per edge: minimum holds if -d >= 0 on the box
// or C_min N - d² >= 0; maximum if d >= 0 or C_max N - d² >= 0
// (generic_bcc.hpp, "Angle forms"); per face angle: -s >= 0 or F M - s² >= 0.
bool verify_box(const Subject& s, const Box& b, const Claim& c, int* fail, std::array<double, 4>& smear) {
    const std::vector<bcc::OutTet> tets = box_tets(s, b);
    const auto fb = all_forms(s, b, tets), fm = all_forms(s, centre(b), tets);
    const auto ok = [&](int j, int f, bool strict) {
        const auto J = static_cast<std::size_t>(j);
        return verify_form(s, b, tets[J], f, c, strict, form_of(fb[J], f, c), form_of(fm[J], f, c).v);
    };
    const auto failed = [&](int j, int f, int kind) {
        const DI g = form_of(fb[static_cast<std::size_t>(j)], f, c);
        for (std::size_t i = 0; i < static_cast<std::size_t>(b.m); ++i)
            smear[i] = std::max(-g.d[i].lower(), g.d[i].upper()) * (b.hi[i] - b.lo[i]);
        *fail = kind;
        return false;
    };
    for (int j = 0; j < static_cast<int>(fb.size()); ++j) {
        if (!ok(j, 0, true)) return failed(j, 0, 0);
        // Either alternative proves a bound; the one matching the sign of d at
        // the centre is tried first (only the cost depends on the order).
        for (int e = 0; e < 6; ++e) {
            const bool acute = fm[static_cast<std::size_t>(j)].di.dot[static_cast<std::size_t>(e)].v.lower() > 0;
            const int s1 = 1 + 2 * e, q1 = 2 + 2 * e, s2 = 13 + 2 * e, q2 = 14 + 2 * e;
            if (!(acute ? ok(j, q1, false) || ok(j, s1, false) : ok(j, s1, false) || ok(j, q1, false)))
                return failed(j, acute ? q1 : s1, 1);
            if (!(acute ? ok(j, s2, false) || ok(j, q2, false) : ok(j, q2, false) || ok(j, s2, false)))
                return failed(j, acute ? s2 : q2, 2);
        }
        for (int q = 0; q < 12; ++q) {
            const bool acute = fm[static_cast<std::size_t>(j)].fa.dot[static_cast<std::size_t>(q)].v.lower() > 0;
            const int s1 = 25 + 2 * q, q1 = 26 + 2 * q;
            if (!(acute ? ok(j, q1, false) || ok(j, s1, false) : ok(j, s1, false) || ok(j, q1, false)))
                return failed(j, acute ? q1 : s1, 4);
        }
    }
    return true;
}

}  // namespace

std::vector<bcc::Stencil> admissible_stencils(const Key& k, const std::vector<Param>& ps, const Box& b) {
    const RoundUp guard;
    std::array<BI, 6> u{};
    for (std::size_t i = 0; i < ps.size(); ++i)
        if (ps[i].index >= 4) u[static_cast<std::size_t>(ps[i].index - 4)] = BI(b.lo[i], b.hi[i]);
    // adm[f]: the signs admitted for the quad of the face without vertex f
    // ({0}: no quad there); adm[4]: for the inside quad.  A sign the box
    // decides is admitted alone; an undecided one, or a zero (whose parity
    // fallback takes one of the two diagonals), admits both.
    const bcc::DelaunaySigns s = bcc::delaunay_signs(k.sign, u);
    const auto admitted = [](const std::optional<int>& x, bool quad) {
        if (!quad) return std::vector<int>{0};
        if (x && *x != 0) return std::vector<int>{*x};
        return std::vector<int>{-1, 1};
    };
    std::array<std::vector<int>, 5> adm;
    for (int f = 0, a, bb, r; f < 4; ++f)
        adm[static_cast<std::size_t>(f)] = admitted(s.face[static_cast<std::size_t>(f)], quad_face(k, f, a, bb, r));
    int a = -1, bb = -1, r0 = -1, r1 = -1;
    adm[4] = admitted(s.inside, inside_quad(k, a, bb, r0, r1));
    return stencils_of_signs(k.sign, adm, [&](const std::array<int, 4>& fs, int inside) {
        return bcc::resolve_delaunay(k.sign, k.parity, fs, inside);
    });
}

std::vector<bcc::Stencil> stencils_of_signs(const std::array<int, 4>& sign, const std::array<std::vector<int>, 5>& adm,
                                            const std::function<bcc::Diagonals(const std::array<int, 4>&, int)>& resolve) {
    std::vector<bcc::Stencil> out;
    std::array<std::size_t, 5> at{};  // an odometer over the combinations
    for (bool more = true; more;) {
        std::array<int, 4> fs{};
        for (std::size_t f = 0; f < 4; ++f) fs[f] = adm[f][at[f]];
        const bcc::Diagonals d = resolve(fs, adm[4][at[4]]);
        if (!bcc::is_cyclic(sign, d)) {
            const bcc::Stencil st = bcc::stencil_with(sign, d);
            if (std::none_of(out.begin(), out.end(), [&](const bcc::Stencil& o) { return same(o, st); })) out.push_back(st);
        }
        more = false;
        for (std::size_t q = 0; q < 5 && !more; ++q) {
            if (++at[q] < adm[q].size()) more = true;
            else at[q] = 0;
        }
    }
    return out;
}

KeyProof prove_key(const Key& k, const bcc::Alphas& al, const Claim& c, int max_depth, long max_leaves, FaceRule rule) {
    return prove_subject(region_subject(k, al, rule), c, max_depth, max_leaves);
}

KeyProof prove_subject(const Subject& sub, const Claim& c, int max_depth, long max_leaves) {
    const RoundUp guard;
    KeyProof out;
    const std::vector<Param>& ps = sub.ps;
    Box root;
    root.m = static_cast<int>(ps.size());
    for (std::size_t i = 0; i < ps.size(); ++i) root.lo[i] = ps[i].root_lo, root.hi[i] = ps[i].root_hi;
    out.root = root;
    // Depth first, lower half first; a box is split at the midpoint of one
    // side.  The split string: '0' a verified leaf, '1' + j a split of side j.
    struct Item {
        Box b;
        int depth;
    };
    std::vector<Item> stack{{root, 0}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        int fail = 0;
        std::array<double, 4> smear{};
        if (verify_box(sub, it.b, c, &fail, smear)) {
            out.splits += '0';
            ++out.leaves;
            continue;
        }
        if (out.leaves >= max_leaves) {  // over budget: no proof
            out.ok = false;
            out.fail_kind = 3;
            return out;
        }
        // Split the side with the largest smear of the failed form (the
        // first on ties): a form that does not depend on a parameter never
        // splits its side.  The widest side if no smear is positive and finite.
        int s = -1;
        for (int j = 0; j < it.b.m; ++j) {
            const auto J = static_cast<std::size_t>(j);
            if (smear[J] > 0 && smear[J] < HUGE_VAL && (s < 0 || smear[J] > smear[static_cast<std::size_t>(s)])) s = j;
        }
        if (s < 0)
            for (int j = 0; j < it.b.m; ++j)
                if (s < 0 || it.b.hi[static_cast<std::size_t>(j)] - it.b.lo[static_cast<std::size_t>(j)] >
                                 it.b.hi[static_cast<std::size_t>(s)] - it.b.lo[static_cast<std::size_t>(s)])
                    s = j;
        if (s < 0 || it.depth >= max_depth) {
            out.ok = false;
            out.fail_kind = fail;
            out.fail_box = it.b;
            for (int j = 0; j < it.b.m; ++j)
                out.fail_point[static_cast<std::size_t>(j)] = 0.5 * (it.b.lo[static_cast<std::size_t>(j)] + it.b.hi[static_cast<std::size_t>(j)]);
            return out;
        }
        out.splits += static_cast<char>('1' + s);
        ++out.split_fails[static_cast<std::size_t>(fail)];
        const auto ss = static_cast<std::size_t>(s);
        const double mid = 0.5 * (it.b.lo[ss] + it.b.hi[ss]);
        Item lo = it, hi = it;
        lo.b.hi[ss] = mid, hi.b.lo[ss] = mid;
        lo.depth = hi.depth = it.depth + 1;
        stack.push_back(hi);
        stack.push_back(lo);
    }
    out.ok = true;
    return out;
}

// "key CODE m lo_0 hi_0 .. lo_{m-1} hi_{m-1} CMIN CMAX CFACE WMIN_0 ..
// WMIN_{m-1} WMAX_0 .. WMAX_{m-1} WFACE_0 .. WFACE_{m-1} SPLITS": root box
// ends (multiples of 2^-20), the key's claim (2^-40), its witnesses (2^-24),
// the split string.
std::string certificate_line(const Key& k, const KeyProof& p) { return "key " + code_of(k) + " " + proof_fields(p); }

std::string dyadic40(double x) {
    std::ostringstream o;
    o << static_cast<long long>(std::ldexp(x, 40)) << "/1099511627776";
    return o.str();
}

std::string proof_fields(const KeyProof& p, bool with_claim, const Subject* a15) {
    std::ostringstream o;
    o << p.root.m;
    const auto dy = [&](double x, int e) { o << " " << static_cast<long long>(std::ldexp(x, e)) << "/" << (1LL << e); };
    for (std::size_t j = 0; j < static_cast<std::size_t>(p.root.m); ++j) dy(p.root.lo[j], 20), dy(p.root.hi[j], 20);
    if (with_claim) dy(p.claim.cmin, 40), dy(p.claim.cmax, 40), dy(p.claim.cface, 40);
    for (const Witness* w : {&p.wmin, &p.wmax, &p.wface})
        for (std::size_t j = 0; j < static_cast<std::size_t>(p.root.m); ++j) {
            a15::Fraction end{};
            if (a15 && a15_exact_end(*a15, j, w->x[j], end)) o << " " << end.num << "/" << end.den;
            else dy(w->x[j], 24);
        }
    o << " " << p.splits;
    return o.str();
}

}  // namespace bcc_prover
}  // namespace warpmesh
