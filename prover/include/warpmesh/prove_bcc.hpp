// prove_bcc.hpp — the 3D prover for the BCC generic tetrahedron
// (generic_bcc.hpp; proofs/README.md, "The BCC space") and for the junction
// keys of multi-material meshes (generic_bcc_materials.hpp; proofs/README.md,
// "Junction keys (3D, bcc_junctions.cert)").
#pragma once

#include <algorithm>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "warpmesh/mesh3d/generic_a15_keys.hpp"
#include "warpmesh/mesh3d/generic_bcc.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"
#include "warpmesh/mesh3d/generic_bcc_materials.hpp"

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
// A threshold from the command line: "0.24999" -> num = 24999 (over
// 100000; at most 5 decimals, in (0, 1/2)); false if it is not one.
bool parse_alpha(const std::string& s, std::int64_t& num);
// One parameter: t of vertex i warped along direction w; u of local edge e.
Param warp_param(int i, int w, const bcc::Alphas& al);
Param cut_param(int e, const bcc::Alphas& al);

// ---- junction keys (proofs/README.md, "Junction keys (3D, bcc_junctions.cert)") ----
// A background tetrahedron where three or four materials meet
// (generic_bcc_materials.hpp: JunctionKey, its symmetries, canonical form
// and code; the cone stencil junction_stencil over junction_points).
using bcc::JunctionKey;
// The consistency rules of the junction key space: letters by first
// appearance with at least three of them (so at most one vertex warped);
// the warped vertex, and only it, carries a warp direction, one of the 14
// (a vertex with a material never moved; a warped vertex moved along a cut
// lattice edge; its material is not recorded, so a warp along a
// tetrahedron edge constrains nothing the key holds: the vertex it went
// towards is unwarped, being not the warped one, and its material differs
// from a material the key does not name); the parity bit 0 where the cone
// stencil has no quad on a long edge (has_junction_parity_quad).
bool junction_consistent(const JunctionKey& k);
// Every canonical consistent junction key, in canonical order (encode).
std::vector<JunctionKey> enumerate_junction_keys();
// The key's parameters: t of the warped vertex in [0, α_e] (its direction's
// edge type), then u in [α_e, 1 − α_e] of each edge whose ends are unwarped
// with different letters (the cut edges), by local edge index.
std::vector<Param> junction_params(const JunctionKey& k, const bcc::Alphas& al);
// The cone tetrahedra of face f (the face without local vertex f) of the
// key's stencil, in the stencil's order: those whose three points other
// than the centre lie on face f (bcc::point_on_face).
std::vector<bcc::OutTet> junction_face_tets(const JunctionKey& k, int f);
// The parameters those tetrahedra depend on, a sub-list of junction_params
// in its order: t of the warped vertex (the centre, the average of the four
// vertices, moves with it) and u of the cut edges of face f (its cut points
// and its face point, the average of its three cut points).  No point of a
// face's tetrahedra depends on any other parameter, so a claim proved over
// the sub-list's box holds over the key's whole box.
std::vector<Param> junction_face_params(const JunctionKey& k, int f, const bcc::Alphas& al);

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
// What the branch and bound and the witness search run on: a one-region
// key's stencil under a face rule (generic_points), or the cone tetrahedra
// of one face of a junction key (junction_points12), with its parameters
// (at most 4: a one-region key has at most 4, a junction face its face's
// three cut edges and the warp).  `seed` seeds the witness search (the
// key's code; a junction face's: its code and the face), so a subject's
// proof is reproducible alone.
struct Subject {
    Key key;  // one region: the key; junction: junction_config (its warps)
    std::vector<Param> ps;
    FaceRule rule = FaceRule::parity;
    bool junction = false;
    std::vector<bcc::OutTet> tets;  // junction: the face's cone tetrahedra
    std::string seed;
    // An A15 key (generic_a15_keys.hpp) of this class, or -1: `key` holds
    // its signs and warps (parity 0), its points are a15::generic_points and
    // its stencils those of the A15 Delaunay rule (a15_subject).
    int a15_class = -1;
    a15::Alphas a15_alphas{};  // an A15 key's thresholds (its exact parameter box)
};
Subject region_subject(const Key& k, const bcc::Alphas& al, FaceRule rule = FaceRule::parity);

// ---- A15 keys (issue 51; generic_a15.hpp, generic_a15_keys.hpp) --------------
// The subject of A15 key k under thresholds al: its parameters
// (a15::key_params: lo, hi the exact ends rounded to nearest, the root box
// their dyadic enclosure as for BCC keys), seeded by its code.
Subject a15_subject(const a15::Key& k, const a15::Alphas& al);
// The A15 key an A15 subject holds.
inline a15::Key a15_key(const Subject& s) { return {s.a15_class, s.key.sign, s.key.warp}; }
// The stencils the A15 Delaunay rule admits on box b of subject s: as
// admissible_stencils, with a15::face_form and a15::inside_form enclosed in
// outward-rounded intervals; an enclosure containing 0 admits both signs (a
// tie goes to one of the two diagonals by the face's global order, which
// the local frame does not know), and the cyclic n- = 3 combinations, which
// no point realises (a strict total order on the three - vertices), are
// skipped.  Every stencil the rule chooses at a point of b is among them.
std::vector<bcc::Stencil> admissible_a15_stencils(const Subject& s, const Box& b);
// The A15 rule's stencil at parameter values x, as the mesher splits the
// key's reference tetrahedron itself (a background tetrahedron at its
// reference coordinates): a15::delaunay_diagonals, a face quad's tie going
// by the lexicographic order of those coordinates, the inside quad's against
// the face (a, b, r0).  Each x[i] is a multiple of 2^-24 (the forms are
// decided in double) or the nearest double of an exact end of its parameter
// (a15_exact_end; the forms are then decided in exact rationals, so that an
// exact tie at a corner of the box is seen).  For witnesses only, not on
// the proof path.
bcc::Stencil a15_stencil_at(const Subject& s, const double* x);
// Whether x is the nearest double of an exact end of parameter i of A15
// subject s and not a multiple of 2^-24 (a witness coordinate the
// certificate writes as that end's exact rational, `num`/`den`).
bool a15_exact_end(const Subject& s, std::size_t i, double x, a15::Fraction& end);
Subject junction_subject(const JunctionKey& k, int face, const bcc::Alphas& al);
// The subject's 15 points (one region: generic_points' ten, the rest 0;
// junction: junction_points12) at t, u.
template <class T>
std::array<bcc::Vec<T>, 15> subject_points(const Subject& s, const std::array<T, 4>& t, const std::array<T, 6>& u) {
    if (s.junction) return bcc::junction_points12<T>(s.key, t, u);
    const std::array<bcc::Vec<T>, 10> g = s.a15_class >= 0 ? a15::generic_points<T>(a15_key(s), t, u) : bcc::generic_points<T>(s.key, t, u);
    std::array<bcc::Vec<T>, 15> p{};
    std::copy(g.begin(), g.end(), p.begin());
    return p;
}

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
// The same for any subject (prove_key is it on region_subject).
KeyProof prove_subject(const Subject& s, const Claim& c, int max_depth = default_max_depth, long max_leaves = 1L << 40);
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
// The enumeration both lattices' admissible stencils share: adm[f] (f < 4)
// the signs admitted for the quad of the face without vertex f, adm[4] those
// of the inside quad ({0}: no quad); every combination is resolved into
// diagonals by `resolve(face_signs, inside_sign)`, and the stencils of the
// non-cyclic ones (stencil_with) are returned, distinct, in the order found.
std::vector<bcc::Stencil> stencils_of_signs(const std::array<int, 4>& sign, const std::array<std::vector<int>, 5>& adm,
                                            const std::function<bcc::Diagonals(const std::array<int, 4>&, int)>& resolve);

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
// The same for any subject (its own parameters and seed); an A15 subject's
// search also tries the exact corners of its box (targets.cpp,
// try_exact_corners).
Witness search_subject(const Subject& s, int sign, const std::array<double, 4>* start = nullptr);
double subject_witness_cos(const Subject& s, const std::array<double, 4>& x, int sign);
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
// The cap for the angles (degrees): cos² rounded to 2^-40; a face angle of
// 0 (the default) is no cap on the face angle (cos² 1).  The prover's
// defaults are those of proofs/bcc.cert (at bcc::parity_alphas: the
// witnesses 10.7685 and 164.7019 deg, moved out as bcc-frontier.sh does).
Claim cap_claim(double min_deg, double max_deg, double face_deg = 0);
inline constexpr double default_cap_min_deg = 10.763, default_cap_max_deg = 164.752;
KeyProof prove_key_tight(const Key& k, const bcc::Alphas& al, Margins mg = {}, int max_depth = default_max_depth,
                         FaceRule rule = FaceRule::parity);
// The same for any subject (prove_key_tight is it on region_subject).
KeyProof prove_subject_tight(const Subject& s, Margins mg = {}, int max_depth = default_max_depth);
// One claim for several subjects (a junction key's four faces): made from
// the most extreme of their witnesses (each searched on its own subject) as
// prove_key_tight makes it, every subject proved against it; a failure at a
// point more extreme than the failed subject's witness moves that witness
// there, and doubles the margin unless that made it the most extreme.  One
// proof per subject, all with the same claim (ok false in the first that
// failed, if any).  prove_subject_tight is it on one subject.
std::vector<KeyProof> prove_tight(const std::vector<Subject>& subs, Margins mg = {}, int max_depth = default_max_depth);
// The key's line of the certificate (proofs/README.md, "The BCC certificate").
std::string certificate_line(const Key& k, const KeyProof& p);
// A proof's fields as certificate_line writes them after the code: "m lo_0
// hi_0 .. CMIN CMAX CFACE WMIN_0 .. WMAX_0 .. WFACE_0 .. SPLITS" (without
// the claim: a junction face line, whose claim is its key's).  With an A15
// subject, a witness coordinate at an exact end of its parameter
// (a15_exact_end) is written as that rational, "num/den".
std::string proof_fields(const KeyProof& p, bool with_claim = true, const Subject* a15 = nullptr);
// A dyadic double p / 2^40 as the certificates write it, "p/1099511627776".
std::string dyadic40(double x);
// `warpmesh-prove-bcc --junctions` (prove_junctions.cpp): proves every face
// of `keys` (prove_subject_tight on junction_subject) and writes the
// junction certificate to `out`; with `extremes`, prints the witness
// search's extremes instead.  0: written, 1: a face not proved.
int prove_junctions(const std::vector<JunctionKey>& keys, const bcc::Alphas& al, const Margins& mg, bool extremes, const std::string& out);
// `warpmesh-prove-bcc --graded` (prove_graded.cpp): the transition
// templates of graded meshes (generic_octree.hpp), exactly, written to
// `out`.  0: written, 1: a template not positively oriented or no output.
int prove_graded(const std::string& out);
// `warpmesh-prove-bcc` (prove.cpp).
int prove_bcc_main(int argc, char** argv);

}  // namespace warpmesh::bcc_prover
