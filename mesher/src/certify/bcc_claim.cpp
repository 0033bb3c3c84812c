// bcc_claim.cpp — the 3D mesher's view of the compiled-in certificates
// (mesh3d.hpp: bcc_claim; uniform3d.hpp: key_certified,
// certificate_applies), read from the table of the face rule in use — each
// rule's certificate is its own table (bcc_certified.hpp), so a mesh is never
// checked or reported against another rule's claims — which
// cmake/certified_table.cmake compiles in and bcc_certified.cpp parses:
//   alphas   the violation thresholds the proof is about;
//   per key  its claim C_min, C_max (cos² thresholds, dyadic rationals);
//   theorem  the extremes of the keys' claims (the certificate's `claim`).
// θ >= θmin and θ <= θmax (θmax > 90°) are compared through cos² (verify3.cpp);
// the degrees are for reports only.
#include "mesh3d/uniform3d.hpp"
#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"
#include "warpmesh/mesh3d/mesh3d.hpp"

#include <cmath>

namespace warpmesh {

std::optional<BccKeyBound> uniform3d::key_certified(const std::array<bcc::Ivec, 4>& p, const std::array<int, 4>& sign,
                                                    const std::array<int, 4>& warp, FaceRule rule, std::string* code) {
    const bcc::Config key = bcc::key_of(p, sign, warp);
    if (code) *code = bcc::code_of(key);
    return bcc_certified_bound(key, rule);
}

bool uniform3d::key_claim_holds(const std::array<Point3, 4>& q, double cos2_min, double cos2_max) {
    std::array<bcc::Vec<double>, 4> p{};
    for (std::size_t k = 0; k < 4; ++k) p[k] = {q[k].x, q[k].y, q[k].z};
    const auto f = bcc::dihedral_forms<double>(p);
    bool ok = f.volume6 > 0;
    for (std::size_t k = 0; k < 6; ++k) {
        const double d = f.dot[k], d2 = d * d;
        ok = ok && (d <= 0 || d2 <= cos2_min * f.nn[k]) && (d >= 0 || d2 <= cos2_max * f.nn[k]);
    }
    return ok;
}

bool uniform3d::certificate_applies(const bcc::Alphas& a, FaceRule rule) {
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

}  // namespace warpmesh
