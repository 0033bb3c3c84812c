// prove_bcc.hpp — the 3D prover for the BCC generic tetrahedron
// (generic_bcc.hpp; proofs/README.md, "The BCC space").
#pragma once

#include <array>
#include <string>
#include <vector>

#include "warpmesh/generic_bcc.hpp"
#include "warpmesh/generic_bcc_keys.hpp"

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

// The symmetries, canonical forms and codes of keys are generic_bcc_keys.hpp's
// (one definition, shared with the 3D mesher).
using bcc::canonical;
using bcc::code_of;
using bcc::has_parity_quad;
using bcc::Symmetry;
using bcc::transform;

// All canonical consistent keys with some output (at least one - vertex),
// in canonical order; with `all_zero`, the keys whose four vertices are zero
// (output only when the mesher finds the centroid inside).
std::vector<Key> enumerate_keys(bool all_zero = false);

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

// ---- the proof ---------------------------------------------------------------
// The claim: every dihedral angle θ has cos θ <= 0 or cos²θ <= cmin (θ >=
// arccos √cmin), and cos θ >= 0 or cos²θ <= cmax (θ <= 180° − arccos √cmax);
// cmin, cmax dyadic doubles (exact rationals in the certificate).
struct Claim {
    double cmin, cmax;
};
struct Box {
    int m = 0;
    std::array<double, 4> lo{}, hi{};
};
struct KeyProof {
    bool ok = false;
    Box root;
    std::string splits;  // preorder: '1' split, '0' verified leaf
    long leaves = 0;
    int fail_kind = 0;   // 0 orientation, 1 minimum, 2 maximum
    std::array<double, 4> fail_point{};
};
// Branch and bound over the key's root box (bound.cpp).
KeyProof prove_key(const Key& k, const bcc::Alphas& al, const Claim& c, int max_depth = 40);
// The key's line of the certificate: "key CODE m lo hi ... SPLITS" (root box
// ends as multiples of 2^-20).
std::string certificate_line(const Key& k, const KeyProof& p);
// `warpmesh-prove-bcc` (prove.cpp).
int prove_bcc_main(int argc, char** argv);

}  // namespace warpmesh::bcc_prover
