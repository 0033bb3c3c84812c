// bcc_claim.cpp — the claims of the compiled-in 3D certificates as the
// pipeline uses them (bcc_certified.hpp: bcc_claim, bcc_certificate_applies,
// bcc_key_claims, bcc_certification), read from the table of the face rule
// in use — each rule's certificate is its own table, so a mesh is never
// checked or reported against another rule's claims — which
// cmake/certified_table.cmake compiles in and bcc_certified.cpp parses:
//   alphas   the violation thresholds the proof is about;
//   per key  its claim C_min, C_max (cos² thresholds, dyadic rationals);
//   theorem  the extremes of the keys' claims (the certificate's `claim`).
// θ >= θmin and θ <= θmax (θmax > 90°) are compared through cos² (the
// mesher's check, mesh3d/tets3.cpp); the degrees are for reports only.
//
// Junctions.  Where three or four materials meet, the multi-material mesher
// splits the background tetrahedron by the cone stencil; its canonical
// junction key has its own claim in proofs/bcc_junctions.cert (the parity
// face rule), added to the parity rule's key claims (junction_claim) and
// certified on its own (bcc_junction_certification) at that certificate's
// alphas.
//
// Certification.  The certificate of the mesh's face rule (proofs/bcc.cert
// for parity, proofs/bcc_delaunay.cert for the Delaunay face rule; never the
// other rule's) claims, at its alphas, for every key with output (a −
// vertex), that every output tetrahedron is positively oriented with every
// dihedral angle θ in the key's own [θmin, θmax], within the theorem.  Every
// output tetrahedron comes from such a key (all-zero background tetrahedra
// are never output), so at the certificate's alphas none is uncertified.
#include "warpmesh/certify/bcc_certified.hpp"

#include <cmath>
#include <sstream>
#include <string_view>

namespace warpmesh {

bool bcc_certificate_applies(const bcc::Alphas& a, FaceRule rule) {
    const std::optional<bcc::Alphas> c = bcc_certified_alphas(rule);
    return c && c->long_num * a.long_den == a.long_num * c->long_den && c->short_num * a.short_den == a.short_num * c->short_den;
}

std::optional<BccClaim> bcc_claim(FaceRule rule) {
    const std::optional<bcc::Alphas> a = bcc_certified_alphas(rule);
    const std::optional<BccKeyBound> t = bcc_certified_theorem(rule);
    if (!a || !t) return std::nullopt;
    return BccClaim{*a, t->min_deg, t->max_deg, std::ldexp(static_cast<double>(t->cmin_num), -40),
                    std::ldexp(static_cast<double>(t->cmax_num), -40)};
}

BccKeyClaims bcc_key_claims(FaceRule rule) {
    BccKeyClaims c;
    c.claim = [rule](const bcc::Config& key) -> std::optional<BccKeyClaim> {
        const std::optional<BccKeyBound> b = bcc_certified_bound(key, rule);
        if (!b) return std::nullopt;
        return BccKeyClaim{std::ldexp(static_cast<double>(b->cmin_num), -40), std::ldexp(static_cast<double>(b->cmax_num), -40)};
    };
    c.source = bcc_certificate_path(rule);
    if (rule == FaceRule::parity && bcc_junction_certified_alphas()) {
        c.junction_claim = [](const bcc::JunctionKey& key) -> std::optional<BccKeyClaim> {
            const std::optional<BccKeyBound> b = bcc_junction_certified_bound(key);
            if (!b) return std::nullopt;
            return BccKeyClaim{std::ldexp(static_cast<double>(b->cmin_num), -40), std::ldexp(static_cast<double>(b->cmax_num), -40)};
        };
        c.source += " and proofs/bcc_junctions.cert";
    }
    return c;
}

BccCertification bcc_junction_certification(const bcc::Alphas& a) {
    BccCertification c;
    const std::optional<bcc::Alphas> j = bcc_junction_certified_alphas();
    const std::optional<BccKeyBound> t = bcc_junction_certified_theorem();
    c.certified = j && t && j->long_num * a.long_den == a.long_num * j->long_den && j->short_num * a.short_den == a.short_num * j->short_den;
    if (c.certified) c.min_deg = t->min_deg, c.max_deg = t->max_deg;
    else
        c.uncertified_reason = j ? "no certificate of the junction keys for these alphas: proofs/bcc_junctions.cert is at other alphas"
                                 : "this build has no certificate of the junction keys (proofs/bcc_junctions.cert): the angles of "
                                   "junction tetrahedra are measured, not certified";
    return c;
}

namespace generated {
extern const std::string_view certified_bcc_graded_claim;
}

namespace {

// The templates' claim line "claim CMIN CMAX CFACE" (rationals p/q), or
// nothing (no certificate in the build, or a line that does not parse).
std::optional<BccKeyClaim> graded_claim() {
    std::istringstream in{std::string(generated::certified_bcc_graded_claim)};
    std::string word;
    BccKeyClaim c;
    if (!(in >> word) || word != "claim") return std::nullopt;
    for (double* x : {&c.cos2_min, &c.cos2_max}) {
        long double p = 0, q = 0;
        char slash = 0;
        if (!(in >> p >> slash >> q) || slash != '/' || !(q > 0)) return std::nullopt;
        *x = static_cast<double>(p / q);
    }
    return c;
}

}  // namespace

BccCertification bcc_template_certification() {
    BccCertification c;
    const std::optional<BccKeyClaim> claim = graded_claim();
    c.certified = claim.has_value();
    if (c.certified) {
        c.min_deg = std::acos(std::sqrt(claim->cos2_min)) * 180 / M_PI;
        c.max_deg = 180 - std::acos(std::sqrt(claim->cos2_max)) * 180 / M_PI;
    } else {
        c.uncertified_reason = "this build has no certificate of the graded templates (proofs/bcc_graded.cert): their angles are "
                               "measured, not certified";
    }
    return c;
}

BccKeyClaim bcc_template_claim() { return graded_claim().value_or(BccKeyClaim{}); }

BccCertification bcc_certification(FaceRule rule, const bcc::Alphas& alphas) {
    BccCertification c;
    const std::optional<BccClaim> claim = bcc_claim(rule);
    const std::string cert = bcc_certificate_path(rule);
    c.certified = bcc_certificate_applies(alphas, rule);
    if (c.certified) c.min_deg = claim->min_deg, c.max_deg = claim->max_deg;
    else
        c.uncertified_reason = claim ? "no certificate for these alphas: " + cert + " (face rule " + face_rule_name(rule) + ") is at other alphas"
                                     : std::string("this build has no certificate of the ") + face_rule_name(rule) + " face rule (" + cert +
                                           "): the angles are measured, not certified";
    return c;
}

}  // namespace warpmesh
