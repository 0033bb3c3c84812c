// prove_bcc.hpp — the 3D prover for the BCC generic tetrahedron
// (generic_bcc.hpp; proofs/README.md, "The BCC space").
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "warpmesh/mesh3d/generic_bcc.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"

namespace warpmesh::bcc_prover {

// A key is a bcc::Config: per local vertex its post-warp sign and, for a zero
// vertex, its warp direction (or bcc::stay); the parity bit, kept only where
// the stencil has a quad on a long edge (else 0).
using Key = bcc::Config;

// Whether the configuration satisfies the consistency rules of
// proofs/README.md ("The BCC space"): only zero vertices carry a warp; two
// vertices never warp towards each other along their common edge; a vertex
// that warped along a tetrahedron edge towards a zero vertex found it
// unwarped then, so that vertex warped (later, elsewhere) and is not `stay`;
// the parity bit is 0 where no parity quad exists.
bool consistent(const Key& k);
// The local vertex (0..3) that vertex i reaches along lattice direction w
// (0..13; `stay`: none), or -1 if that lattice point is not a vertex of the
// reference tetrahedron.
int warp_target(int i, int w);

// The symmetries, canonical forms and codes of keys are generic_bcc_keys.hpp's
// (one definition, shared with the 3D mesher).
using bcc::canonical;
using bcc::code_of;
using bcc::has_parity_quad;
using bcc::Symmetry;
using bcc::transform;

// The face of key k's tetrahedron without local vertex f, if it holds a
// quad: its − vertices a < b and its + vertex r (else false).
inline bool quad_face(const Key& k, int f, int& a, int& b, int& r) { return bcc::quad_face(k.sign, f, a, b, r); }
inline bool inside_quad(const Key& k, int& a, int& b, int& r0, int& r1) { return bcc::inside_quad(k.sign, a, b, r0, r1); }

// All canonical consistent keys with some output (at least one - vertex),
// in canonical order; with `all_zero`, the keys whose four vertices are zero
// (never output: generic_bcc.hpp, step 6).
std::vector<Key> enumerate_keys(bool all_zero = false);
// The canonical key with output whose code_of is `code`, if there is one.
std::optional<Key> key_with_code(const std::string& code);

// The key's parameters: per warped vertex its t in [0, α_e], per (-, +) edge
// its u in [α_e, 1 − α_e]; `index` says which (0..3: t of vertex, 4 + e: u of edge e).
// lo, hi: the exact box's ends as doubles (nearest); root_lo, root_hi: the
// prover's root box, dyadic multiples of 2^-20 containing the exact box.
struct Param {
    int index;
    double lo, hi;
    double root_lo, root_hi;
};
std::vector<Param> key_params(const Key& k, const bcc::Alphas& al);

// ---- the face rule -----------------------------------------------------------
// Which rule splits the quads (generic_bcc.hpp, "The diagonal choices":
// FaceRule, its names and parser): parity (the mesher's, proofs/bcc.cert) or
// the Delaunay face rule (proofs/bcc_delaunay.cert).  The key space is the
// same for both.
using warpmesh::FaceRule;

// ---- the proof ---------------------------------------------------------------
// The claim: every dihedral angle θ has cos θ <= 0 or cos²θ <= cmin (θ >=
// arccos √cmin), and cos θ >= 0 or cos²θ <= cmax (θ <= 180° − arccos √cmax);
// every face angle φ has cos φ <= 0 or cos²φ <= cface (φ >= arccos √cface);
// dyadic doubles (exact rationals in the certificate).
struct Claim {
    double cmin, cmax, cface;
};
struct Box {
    int m = 0;
    std::array<double, 4> lo{}, hi{};
};
// A witness: a point x of the key's box (multiples of 2^-24 inside the exact
// box) and the cos of its extreme dihedral angle there (double, a target).
struct Witness {
    std::array<double, 4> x{};
    double cos = 0;
};
struct KeyProof {
    bool ok = false;
    Claim claim{};             // the key's own claim
    Witness wmin, wmax, wface;  // its smallest / largest dihedral, smallest face angle witness
    Box root;
    std::string splits;  // preorder: '1' split, '0' verified leaf
    long leaves = 0;
    int fail_kind = 0;   // 0 orientation, 1 minimum, 2 maximum, 3 over the leaf budget, 4 face angle
    std::array<long, 5> split_fails{};  // boxes split because that kind failed (0, 1, 2, 4)
    std::array<double, 4> fail_point{};  // the failed box's centre
    Box fail_box;                        // the failed box
};
// Branch and bound over the key's root box (bound.cpp), giving up after
// max_leaves verified leaves.  With the Delaunay rule every claim is proved,
// box by box, for every stencil the rule admits on the box
// (admissible_stencils).
// A box still failing at depth max_depth (splits from the root) fails the
// key.  48 is 12 halvings per side with 4 parameters: under the Delaunay
// rule the n- = 2, n+ = 2 prism's box corner where its face quads' and
// inside quad's ties meet (all cut fractions at α; up to six stencils
// admitted there) needs more than 40 to prove a minimum within 0.01° of its
// witness (tests/test_bcc_prover.cpp, prism_corner_needs_depth_48).
inline constexpr int default_max_depth = 48;
KeyProof prove_key(const Key& k, const bcc::Alphas& al, const Claim& c, int max_depth = default_max_depth, long max_leaves = 1L << 40,
                   FaceRule rule = FaceRule::parity);
// The stencils the Delaunay face rule admits on box b of key k's parameters
// ps: each quad face's face_form and (n- = 2, n+ = 2) the inside_form,
// enclosed in outward-rounded intervals, admit the sign +1, −1 or both (an
// enclosure containing 0: a tie, or a box where the sign changes, goes to
// one of the two); every combination of admitted signs is resolved
// (resolve_delaunay) except the cyclic ones of an n- = 3 prism, which no
// point realises (face_form(a, b, r) = P_b − P_a: P_a < P_b < P_c < P_a is
// impossible, and a tie, resolved by the parity rule, breaks no order);
// distinct stencils, in the order found.  Every stencil the rule chooses at
// a point of b is among them.
std::vector<bcc::Stencil> admissible_stencils(const Key& k, const std::vector<Param>& ps, const Box& b);

// ---- per-key targets (targets.cpp; not on the proof path) -------------------
// The key's ten points in double at the parameter values x[0 .. ps.size()).
std::array<bcc::Vec<double>, 10> key_points(const Key& k, const std::vector<Param>& ps, const double* x);
// The key's stencil at x under the rule (Delaunay: the forms' signs in
// double, exact on the 2^-24 grid; ties to the parity rule).
bcc::Stencil stencil_at(const Key& k, const std::vector<Param>& ps, const double* x, FaceRule rule);
// The cos of the key's extreme angle at x: the smallest dihedral angle's
// (sign = +1), the largest's (sign = -1) or the smallest face angle's (2).
double witness_cos(const Key& k, const std::vector<Param>& ps, const std::array<double, 4>& x, int sign,
                   FaceRule rule = FaceRule::parity);
// A double search of the key's box for that extreme (from `start` if given),
// on the 2^-24 grid; deterministic per key.
Witness search_witness(const Key& k, const std::vector<Param>& ps, int sign, const std::array<double, 4>* start = nullptr,
                       FaceRule rule = FaceRule::parity);
// The claim's cos² for a witness with this cos: the angle moved outward by
// margin_deg, to first order, rounded up to 2^-40.
double claim_cos2(double cos, double margin_deg);
// The key's proof: witnesses, claims the witnesses' angles moved outward by
// the margins (0.004 deg at the minimum and the face-angle minimum, 0.04 deg
// at the maximum: within the 0.01 / 0.1 deg of "tight"), proved within a
// budget of `budget` leaves.  A failure at a point more extreme than the
// witness moves the witness there; a failure elsewhere doubles that margin.
// An exhausted budget first doubles every margin once (still tight), then
// the budget, up to `max_budget`, then the margin whose failures caused most
// splits (and any other that caused at least a quarter as many); once a
// margin is 64 times its start (0.256 deg, 2.56 deg) the budget is lifted (32 attempts in all; then the
// caps themselves, without budget).  The key's claim is then loose (at most
// the cap), and its gap says so; ok false only if even that fails.
// No key's claim is looser than `cap` (the theorem's bounds when every key
// is proved at its margins; the prover's --cap-min-deg, --cap-max-deg); a
// key whose witness lies within tight_min_deg / tight_max_deg of the cap
// claims the cap (so the theorem is the caps, and those keys stay tight).
struct Margins {
    double min_deg = 0.004, max_deg = 0.04, face_deg = 0.004;
    long budget = 1000, max_budget = 64000;
    double tight_min_deg = 0.009, tight_max_deg = 0.09;  // a cap this close to the witness is claimed
    Claim cap{1, 1, 1};                                   // no cap on the face angle
};
// The cap for the angles (degrees): cos² rounded to 2^-40.  The prover's
// defaults are those of proofs/bcc.cert (at bcc::parity_alphas: the
// witnesses 10.7685 and 164.7019 deg, moved out as bcc-frontier.sh does).
Claim cap_claim(double min_deg, double max_deg);
inline constexpr double default_cap_min_deg = 10.763, default_cap_max_deg = 164.752;
KeyProof prove_key_tight(const Key& k, const bcc::Alphas& al, Margins mg = {}, int max_depth = default_max_depth,
                         FaceRule rule = FaceRule::parity);
// The key's line of the certificate (proofs/README.md, "The BCC certificate").
std::string certificate_line(const Key& k, const KeyProof& p);
// `warpmesh-prove-bcc` (prove.cpp).
int prove_bcc_main(int argc, char** argv);

}  // namespace warpmesh::bcc_prover
