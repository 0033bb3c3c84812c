// bcc_claim.cpp — the 3D certificate's claim, compiled in (mesh3d.hpp:
// bcc_claim).  cmake/certified_table.cmake copies the `alphas` and `claim`
// lines of proofs/bcc.cert into certified_bcc_claim:
//   alphas <long num>/<den> <short num>/<den>
//   claim <C_min num>/<den> <C_max num>/<den>
// C = cos²θ of the bounds (dyadic rationals, proofs/README.md "The BCC
// space"): θ >= θmin and θ <= θmax (θmax > 90°).  The degrees are for
// reports only; verification compares cos² (mesh3d's verify).  And the
// codes of the certificate's keys, one a line, which key_certified looks a
// background tetrahedron's canonical key up in (generic_bcc_keys.hpp).
#include <cmath>
#include <numbers>
#include <sstream>

#include <unordered_set>

#include "uniform3d/uniform3d.hpp"
#include "warpmesh/generic_bcc_keys.hpp"
#include "warpmesh/mesh3d.hpp"

namespace warpmesh::generated {
extern const std::string_view certified_bcc_claim;
extern const std::string_view certified_bcc_keys;
}

namespace warpmesh {
namespace {

bool ratio(std::istream& in, std::int64_t& num, std::int64_t& den) {
    char slash = 0;
    return static_cast<bool>(in >> num >> slash >> den) && slash == '/' && den > 0;
}

std::optional<BccClaim> parse_claim(std::string_view text) {
    std::istringstream in{std::string(text)};
    std::string word;
    BccClaim c{};
    bool have_alphas = false, have_claim = false;
    while (in >> word) {
        if (word == "alphas") {
            have_alphas = ratio(in, c.alphas.long_num, c.alphas.long_den) && ratio(in, c.alphas.short_num, c.alphas.short_den);
        } else if (word == "claim") {
            std::int64_t n1 = 0, d1 = 1, n2 = 0, d2 = 1;
            have_claim = ratio(in, n1, d1) && ratio(in, n2, d2);
            c.cos2_min = static_cast<double>(n1) / static_cast<double>(d1);
            c.cos2_max = static_cast<double>(n2) / static_cast<double>(d2);
        } else {
            return std::nullopt;
        }
    }
    if (!have_alphas || !have_claim || !(c.cos2_min > 0 && c.cos2_min < 1 && c.cos2_max > 0 && c.cos2_max < 1))
        return std::nullopt;
    const double deg = 180 / std::numbers::pi;
    c.min_deg = std::acos(std::sqrt(c.cos2_min)) * deg;
    c.max_deg = 180 - std::acos(std::sqrt(c.cos2_max)) * deg;
    return c;
}

}  // namespace

bool uniform3d::key_certified(const std::array<bcc::Ivec, 4>& p, const std::array<int, 4>& sign, const std::array<int, 4>& warp,
                              std::string* code) {
    static const std::unordered_set<std::string_view> keys = [] {
        std::unordered_set<std::string_view> k;
        std::string_view t = generated::certified_bcc_keys;
        while (!t.empty()) {
            const std::size_t nl = t.find('\n');
            if (nl != 0) k.insert(t.substr(0, nl));
            if (nl == std::string_view::npos) break;
            t.remove_prefix(nl + 1);
        }
        return k;
    }();
    std::string c = bcc::code_of(bcc::key_of(p, sign, warp));
    const bool found = keys.count(c) != 0;
    if (code) *code = std::move(c);
    return found;
}

bool uniform3d::certificate_applies(const bcc::Alphas& a) {
    const std::optional<BccClaim> c = bcc_claim();
    return c && c->alphas.long_num * a.long_den == a.long_num * c->alphas.long_den &&
           c->alphas.short_num * a.short_den == a.short_num * c->alphas.short_den;
}

std::optional<BccClaim> bcc_claim() {
    static const std::optional<BccClaim> claim = parse_claim(generated::certified_bcc_claim);
    return claim;
}

}  // namespace warpmesh
