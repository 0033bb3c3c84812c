// prove.hpp — the angle prover for the generic square (see proofs/README.md).
//
// `prove_main` implements `warpmesh prove [--out DIR] [--threads N] [--lattice square|rhombic] [--rule R] [--keys I,J,..]`.
// The rest is the prover's API, used by the tests.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "warpmesh/mesh2d/generic_square.hpp"

namespace warpmesh {

int prove_main(int argc, char** argv);

namespace prover {

// The fan rule's thresholds (generic_square.hpp: H0 = fan_threshold_cot =
// 3 + 2^-20), exact doubles.  A diagonal excluded with fan_exclusion_cot =
// H0 (1 + 2^-28) does not qualify in the mesher's double evaluation either; one
// verified with q <= fan_keep_cot = H0 (1 - 2^-28) qualifies there too; a
// diagonal the mesher lets qualify has exact q <= H0 (1 + 2^-33) <
// fan_taken_cot = H0 (1 + 2^-30) (proofs/README.md, "The fan rule").
inline constexpr double fan_h0 = 3.0 + 0x1p-20;
inline constexpr double fan_exclusion_cot = 3.0 + 0x1p-20 + 3 * 0x1p-28 + 0x1p-48;
inline constexpr double fan_keep_cot = 3.0 + 0x1p-20 - 3 * 0x1p-28 - 0x1p-48;
inline constexpr double fan_taken_cot = 3.0 + 0x1p-20 + 3 * 0x1p-30 + 0x1p-50;

// A configuration key: each corner's original sign and warp state.  A
// *junction key* (a multi-material square whose corners carry 3 or 4
// materials; proofs/README.md, "Junction keys") has `junction` set and the
// corners' material classes in `m` (letters 0..3 in order of first appearance
// A, B, C, D); its warps are in both `s` and `m`, its signs `s[c].sign` are 0
// and unused.  `metric`: the lattice whose angles the key's forms measure
// (generic_square.hpp's LatticeMetric; the configurations, in lattice
// coordinates, are the same on both lattices, proofs/README.md "The rhombic
// lattice"): every form of the prover reads it from the key.
struct Key {
    std::array<CornerState, 4> s;
    bool junction = false;
    std::array<MaterialCorner, 4> m{};
    LatticeMetric metric = LatticeMetric::square;
};

// The rule's choice for a key's corners: choose_diagonal of generic_square.hpp
// with the signs, or for a junction key with the material classes (the
// separating test only asks whether two staying corners' materials differ).
// `tie`: the branch and bound asks with TieBreak::either (the mesher breaks
// exact ties by the square's position, union_jack: a box is decided only
// where both tie-breaks take the same diagonal); the point evaluations of
// targets and witnesses with TieBreak::ad (at an exact tie the AD value is
// attained, by the squares whose tie-break is AD).
template <class T>
Choice choose_key_diagonal(DiagonalRule rule, const std::array<Point<T>, 4>& p, const Key& k, TieBreak tie = TieBreak::ad) {
    return k.junction ? choose_diagonal<T>(rule, p, k.m, tie, k.metric) : choose_diagonal<T>(rule, p, k.s, tie, k.metric);
}

// Whether the fan rule may take the centroid fan on the key's squares: its
// corners are all inside (generic_square.hpp's all_inside: signs, or for a
// junction key its staying corners share a letter).
inline bool fan_key(DiagonalRule rule, const Key& k) {
    return rule == DiagonalRule::fan && (k.junction ? all_inside(k.m) : all_inside(k.s));
}

// The key's code: key_code(s) (mesh2d/square_keys.hpp, e.g. "-R+U-L-R"), or for a
// junction key its letters and warps (junction_key_code, e.g. "aRaUbscs").
std::string code_of(const Key& k);

// The set of keys a certificate covers.
enum class KeySpace { signs, junctions };
// All junction keys satisfying the material consistency rules of
// proofs/README.md ("Junction keys"), in canonical order (corner A's state
// most significant, a state being letter * 5 + warp).
std::vector<Key> junction_keys();
// For keys[ids[i]] (junction keys), the first i' <= i whose key has the same
// warps and the same separating-rule forcing under `rule` (none, AD, BC): the
// keys of a class have the same configurations and decisions.
std::vector<int> junction_classes(DiagonalRule rule, const std::vector<Key>& keys, const std::vector<int>& ids);

// A key's 8-character code is key_code(key.s) (mesh2d/square_keys.hpp).
// All keys satisfying the consistency rules of proofs/README.md, in the
// canonical order (corner A's state most significant).
std::vector<Key> consistent_keys();
// Whether some affine function has the key's corner signs and the opposite
// sign at the outside neighbour of every outward slide (stencil_admits_flat).
bool flat_compatible(const Key& k);
// The warped corners, in order: the variables t_0.. of the key's box [0,1/2]^m.
std::vector<int> key_vars(const Key& k);

// The switching certificate of an undecided leaf (tag S, bound.cpp): per
// diagonal d (0 AD, 1 BC), k[d] the reference ratio of d (index 3 t + i,
// vertex i of triangle t; -1: every max-angle form of d holds outright), j[2 d],
// j[2 d + 1] the named ratios of the other diagonal (-1: none), and per named
// ratio n and max-angle form 3 t + i of d its multiplier
// lambda[12 d + 6 n + 3 t + i] (< 0: the form holds outright).
struct Switch {
    std::array<std::int8_t, 2> k{-1, -1};
    std::array<std::int8_t, 4> j{-1, -1, -1, -1};
    std::array<double, 24> lambda{};
};

// One leaf box: dimension i is [num[2i], num[2i+1]] / 2^k; diag bit 1 = AD, 2 = BC;
// fan rule: 4 = the fan decided (tag F), 5 = undecided between the fan and a diagonal (tag Y).
struct Leaf {
    std::uint8_t diag = 0;
    int k = 0;
    std::array<std::int64_t, 8> num{};
    double threshold = 0;  // non-zero: the diagonal was decided by the threshold test (see bound.cpp)
    int sw = -1;           // diag 3 with a switching certificate: its index in KeyProof::switches
};

struct KeyProof {
    bool ok = false;
    std::vector<Leaf> leaves;
    std::vector<Switch> switches;
    std::array<double, 4> fail_point{};  // centre of a box that could not be certified
    int fail_kind = 0;                   // what failed there: 0 orientation, 1 min angle, 2 max angle
};

// Branch and bound over the key's t-box: every angle of the chosen triangles
// has cot <= min_cot and cot >= max_cot, both triangles positively oriented.
KeyProof prove_key(DiagonalRule rule, const Key& key, double min_cot, double max_cot,
                   std::size_t max_leaves = 2000000);

// The choice of the rule on a box, evaluated with outward-rounded intervals
// through generic_square.hpp (bit 1 = AD may be taken, bit 2 = BC).
int interval_choice(DiagonalRule rule, const Key& key, const std::array<double, 4>& lo,
                    const std::array<double, 4>& hi);

// "maxmin", "separating" or "fan": the certificate's rule line and file name.
inline const char* rule_name(DiagonalRule r) {
    return name_of(diagonal_rule_names, r).data();
}

// "square" or "rhombic": the certificate's metric line (format 4).
inline const char* metric_name(LatticeMetric m) { return name_of(lattice_metric_names, m).data(); }

// Runs the whole proof for a rule and returns the certificate text.  `key_subset`
// (indices into consistent_keys()) restricts the run, for tests; the claims are
// then over that subset only.  `log` receives a human summary.
// `space` = junctions: the junction keys (separating rule: proofs/materials.cert;
// fan rule: proofs/materials_fan.cert), no flat category, the header line
// `space junctions`.
// `metric` = rhombic: the sign keys measured in the rhombic metric (claims
// and witnesses are bounds on r = dot / cross = sqrt(3) cot(angle)), the
// header `warpmesh-certificate 4` and `metric rhombic`; the square metric
// writes format 3 as before.  The fan rule has no rhombic version.
std::string run_proof(DiagonalRule rule, const std::vector<int>* key_subset, std::string* log,
                      KeySpace space = KeySpace::signs, LatticeMetric metric = LatticeMetric::square);

}  // namespace prover
}  // namespace warpmesh
