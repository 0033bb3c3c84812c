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

#include <string>

#include "warpmesh/mesh3d/generic_bcc.hpp"            // FaceRule, Alphas
#include "warpmesh/mesh3d/generic_bcc_materials.hpp"  // JunctionKey
#include "warpmesh/mesh3d/mesh3d.hpp"       // BccKeyClaims

namespace warpmesh {

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

// The claim of a face rule's certificate (compiled in): its alphas and the
// dihedral bounds, or nullopt when the build has none.
struct BccClaim {
    bcc::Alphas alphas;
    double min_deg, max_deg;
    // cos² thresholds as the certificate states them (dyadic rationals).
    double cos2_min, cos2_max;
};
std::optional<BccClaim> bcc_claim(FaceRule rule = FaceRule::parity);

// Whether the certificate of `rule` is compiled in and at these alphas
// (equal rationals).
bool bcc_certificate_applies(const bcc::Alphas& alphas, FaceRule rule);

// The per-key claims of the certificate of `rule` (cos² thresholds
// p / 2^40), named by its path, for the mesher's verification
// (mesh3d.hpp: BccOptions::verify); for the parity rule also the junction
// keys' (BccKeyClaims::junction_claim, proofs/bcc_junctions.cert) when the
// build has that certificate.
BccKeyClaims bcc_key_claims(FaceRule rule);

// The certification of a mesh split by `rule` at `alphas`: certified iff
// the rule's certificate applies (bcc_certificate_applies); then every
// output tetrahedron comes from a certified key (all-zero background
// tetrahedra are never output) and its angles lie in the theorem's [min_deg,
// max_deg]; else the reason, naming the certificate.
struct BccCertification {
    bool certified = false;
    double min_deg = 0, max_deg = 0;
    std::string uncertified_reason;  // empty when certified
};
BccCertification bcc_certification(FaceRule rule, const bcc::Alphas& alphas);

// ---- junction keys (proofs/bcc_junctions.cert) ------------------------------------
// Multi-material meshes split a background tetrahedron where three or four
// materials meet by the cone stencil (generic_bcc_materials.hpp); its
// canonical junction key (bcc::junction_key_of) has its own claim in
// proofs/bcc_junctions.cert, compiled in when the build has it (the parity
// face rule, the only one multi-material meshes use).  Two-material
// tetrahedra are one-region keys of proofs/bcc.cert.

// The claim of a canonical junction key, or nothing without the certificate.
std::optional<BccKeyBound> bcc_junction_certified_bound(const bcc::JunctionKey& canonical_key);
// The alphas the junction certificate was proved for, or nothing without it.
std::optional<bcc::Alphas> bcc_junction_certified_alphas();
// The junction certificate's theorem: the extremes of its keys' claims.
std::optional<BccKeyBound> bcc_junction_certified_theorem();
// The certification of a multi-material mesh's junction tetrahedra at
// `alphas`: certified iff the junction certificate is compiled in and at
// these alphas (then every junction tetrahedron's dihedral angles lie in
// its theorem's [min_deg, max_deg], every one positively oriented); else
// the reason.
BccCertification bcc_junction_certification(const bcc::Alphas& alphas);

// ---- graded meshes' templates (proofs/bcc_graded.cert) -----------------------------
// A graded mesh (mesh3d/graded.hpp) outputs, beside the stencils' tetrahedra,
// the octree's templates (generic_octree.hpp): fixed polyhedra, certified
// by proofs/bcc_graded.cert at any alphas (no vertex of theirs is warped).
// Certified iff the build has the certificate; then every template's
// dihedral angles lie in its claim's [min_deg, max_deg].
BccCertification bcc_template_certification();
// The templates' claim (cos² thresholds) for verify; zeros without the certificate.
BccKeyClaim bcc_template_claim();

}  // namespace warpmesh
