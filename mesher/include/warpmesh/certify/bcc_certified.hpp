// bcc_certified.hpp — the certified dihedral-angle bounds of the 3D proofs,
// per key, compiled into the library (cmake/certified_table.cmake): one
// table per face rule (generic_bcc.hpp, "The diagonal choices"), each from
// its own certificate — proofs/bcc.cert (the parity rule) and, when the build
// has it, proofs/bcc_delaunay.cert (the Delaunay face rule).  A table knows
// its rule from its certificate (a `face-rule RULE` line; none: parity), so a
// mesh is only ever checked or reported against the certificate of the rule
// that split it.  The 3D mesher looks up the key of each background
// tetrahedron (generic_bcc_keys.hpp, `key_of`) to report or verify the
// bounds of its output; proofs/README.md, "The BCC space".
#pragma once

#include <cstdint>
#include <optional>

#include "warpmesh/core/names.hpp"

#include "warpmesh/mesh3d/generic_bcc.hpp"

namespace warpmesh {

// The rule that splits the quads of the 3D stencils (generic_bcc.hpp, "The
// diagonal choices"): parity (`parity_diagonals`) or the Delaunay face rule
// (`delaunay_diagonals`).
enum class FaceRule { parity, delaunay };
// Their names (reports, certificates' face-rule line, --face-rule, Python's
// face_rule=); parse with value_of(face_rule_names, name).
inline constexpr std::array<Named<FaceRule>, 2> face_rule_names{
    {{FaceRule::parity, "parity"}, {FaceRule::delaunay, "delaunay"}}};
// "parity", "delaunay".
const char* face_rule_name(FaceRule rule);
// The certificate of a rule: "proofs/bcc.cert", "proofs/bcc_delaunay.cert".
const char* bcc_certificate_path(FaceRule rule);

// A key's claim: every output tetrahedron of every configuration of the key
// is positively oriented and every dihedral angle θ has cos θ <= 0 or cos²θ
// <= cmin_num / 2^40 (θ >= min_deg), and cos θ >= 0 or cos²θ <= cmax_num /
// 2^40 (θ <= max_deg).  The degrees are arccos of the exact claim, rounded
// to double (for reports; compare cos² with the exact numbers to verify).
struct BccKeyBound {
    std::uint64_t cmin_num = 0, cmax_num = 0;
    double min_deg = 0, max_deg = 180;
};

// The claim of a canonical key (bcc::key_of) in the certificate of `rule`,
// or nothing if that certificate was missing at build time or the key has no
// output (no - vertex: the all-zero keys, whose tetrahedron is never output).
std::optional<BccKeyBound> bcc_certified_bound(const bcc::Config& canonical_key, FaceRule rule = FaceRule::parity);
// The violation thresholds the certificate of `rule` was proved for (the
// mesher must use them for the bounds to apply), or nothing without it.
std::optional<bcc::Alphas> bcc_certified_alphas(FaceRule rule = FaceRule::parity);
// The whole certificate's theorem: the extremes of the keys' claims.
std::optional<BccKeyBound> bcc_certified_theorem(FaceRule rule = FaceRule::parity);

}  // namespace warpmesh
