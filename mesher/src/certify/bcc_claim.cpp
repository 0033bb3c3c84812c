// bcc_claim.cpp — the 3D certificate's claim, compiled in (mesh3d.hpp:
// bcc_claim).  cmake/certified_table.cmake copies the `alphas` and `claim`
// lines of proofs/bcc.cert into certified_bcc_claim:
//   alphas <long num>/<den> <short num>/<den>
//   claim <C_min num>/<den> <C_max num>/<den>
// C = cos²θ of the bounds (dyadic rationals, proofs/README.md "The BCC
// space"): θ >= θmin and θ <= θmax (θmax > 90°).  The degrees are for
// reports only; verification compares cos² (mesh3d's verify).
#include <cmath>
#include <numbers>
#include <sstream>

#include "warpmesh/mesh3d.hpp"

namespace warpmesh::generated {
extern const std::string_view certified_bcc_claim;
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

std::optional<BccClaim> bcc_claim() {
    static const std::optional<BccClaim> claim = parse_claim(generated::certified_bcc_claim);
    return claim;
}

}  // namespace warpmesh
