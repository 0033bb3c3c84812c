// bcc_certified.cpp — parses the per-key claims of the 3D certificates
// compiled in by cmake/certified_table.cmake (proofs/bcc.cert and, when the
// build has it, proofs/bcc_delaunay.cert: "face-rule RULE" if the certificate
// names one, "alphas L S", then "CODE CMIN CMAX" per key, claims p / 2^40;
// and, in the same form, the junction keys of proofs/bcc_junctions.cert).
// Each table is the rule its own text names (none: parity), whichever
// constant it came in; bcc_certified.hpp states the contract.
#include "warpmesh/certify/bcc_certified.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <string_view>

#include "warpmesh/mesh3d/generic_bcc_keys.hpp"
#include "warpmesh/mesh3d/generic_bcc_materials.hpp"

namespace warpmesh {
namespace generated {
extern const std::string_view certified_bcc_keys;
extern const std::string_view certified_bcc_delaunay_keys;
extern const std::string_view certified_bcc_junction_keys;
}

namespace {

struct BccTable {
    FaceRule rule = FaceRule::parity;
    std::optional<bcc::Alphas> alphas;
    std::map<std::string, BccKeyBound, std::less<>> keys;
    std::optional<BccKeyBound> theorem;
};

// "p/1099511627776" -> p.
std::uint64_t numerator40(const std::string& s) {
    if (s.size() < 15 || s.substr(s.size() - 14) != "/1099511627776") return 0;
    return std::stoull(s.substr(0, s.size() - 14));
}

double degrees(std::uint64_t num, bool obtuse) {
    const double a = std::acos(std::sqrt(std::ldexp(static_cast<double>(num), -40))) * 180 / M_PI;
    return obtuse ? 180 - a : a;
}

BccTable parse_table(std::string_view text) {
    BccTable t;
    std::istringstream in{std::string(text)};
    for (std::string line; std::getline(in, line);) {
        std::istringstream ls(line);
        std::string a, b, c;
        ls >> a >> b >> c;
        if (a == "face-rule") {
            const std::optional<FaceRule> rule = parse_face_rule(b);
            if (!rule) return BccTable{};  // a rule this mesher does not know: no table
            t.rule = *rule;
            continue;
        }
        if (a == "alphas") {
            const auto num = [](const std::string& x) { return std::stoll(x.substr(0, x.find('/'))); };
            const auto den = [](const std::string& x) { return std::stoll(x.substr(x.find('/') + 1)); };
            t.alphas = bcc::Alphas{num(b), den(b), num(c), den(c)};
            continue;
        }
        BccKeyBound k{numerator40(b), numerator40(c), 0, 180};
        k.min_deg = degrees(k.cmin_num, false), k.max_deg = degrees(k.cmax_num, true);
        if (!t.theorem) t.theorem = k;
        if (k.cmin_num > t.theorem->cmin_num) t.theorem->cmin_num = k.cmin_num, t.theorem->min_deg = k.min_deg;
        if (k.cmax_num > t.theorem->cmax_num) t.theorem->cmax_num = k.cmax_num, t.theorem->max_deg = k.max_deg;
        t.keys.emplace(a, k);
    }
    return t;
}

// The table of `rule`: the compiled-in certificate that names it (an empty
// table when none does).
const BccTable& table(FaceRule rule) {
    static const std::array<BccTable, 2> compiled{parse_table(generated::certified_bcc_keys),
                                                  parse_table(generated::certified_bcc_delaunay_keys)};
    static const BccTable none;
    for (const BccTable& t : compiled)
        if (t.rule == rule && t.alphas && !t.keys.empty()) return t;
    return none;
}

// The junction keys' table (proofs/bcc_junctions.cert; empty without it).
const BccTable& junction_table() {
    static const BccTable t = [] {
        BccTable j = parse_table(generated::certified_bcc_junction_keys);
        return j.alphas && !j.keys.empty() ? j : BccTable{};
    }();
    return t;
}

}  // namespace

std::optional<BccKeyBound> bcc_junction_certified_bound(const bcc::JunctionKey& canonical_key) {
    const BccTable& t = junction_table();
    const auto it = t.keys.find(bcc::code_of(canonical_key));
    if (it == t.keys.end()) return std::nullopt;
    return it->second;
}

std::optional<bcc::Alphas> bcc_junction_certified_alphas() { return junction_table().alphas; }

std::optional<BccKeyBound> bcc_junction_certified_theorem() { return junction_table().theorem; }

const char* bcc_certificate_path(FaceRule rule) {
    return rule == FaceRule::delaunay ? "proofs/bcc_delaunay.cert" : "proofs/bcc.cert";
}

std::optional<BccKeyBound> bcc_certified_bound(const bcc::Config& canonical_key, FaceRule rule) {
    const BccTable& t = table(rule);
    const auto it = t.keys.find(bcc::code_of(canonical_key));
    if (it == t.keys.end()) return std::nullopt;
    return it->second;
}

std::optional<bcc::Alphas> bcc_certified_alphas(FaceRule rule) { return table(rule).alphas; }

std::optional<BccKeyBound> bcc_certified_theorem(FaceRule rule) { return table(rule).theorem; }

}  // namespace warpmesh
